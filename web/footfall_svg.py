"""The footfall diagram: six rows (legs 1-6), one bar per stance interval, scrolling in time.

Its rows are coloured as the 3D legs' stance markers are (web/style.py: one palette for the
hexapod and its footfall), built on web/svg.py's frame and axes.
"""

from __future__ import annotations

from collections.abc import Sequence

from sim_core.contract import LEG_NAMES
from web.style import LEG_COLOURS, PAIR_COLOURS
from web.svg import (
    FONT,
    LEFT,
    LINE,
    open_svg,
    panel_frame,
    time_axis_word,
    time_ticks,
    time_window,
    x_ticks,
)

LEG_ORDER = LEG_NAMES  # the paper's legs 1-6, rows top to bottom


def footfall_svg(
    bars: Sequence[Sequence[tuple[float, float]]], t_now: float, window_s: float
) -> str:
    """Six rows (legs 1-6: R1 L1 R2 L2 R3 L3), one rect per stance interval, scrolling."""
    t0, t1 = time_window(t_now, window_s)
    title = f"Footfall, last {window_s:g} s (stance; right legs dark)"
    f = panel_frame(title, t0, t1, 0.0, 6.0, below=LINE)  # a row for the axis word
    out = open_svg("footfall", title, f, t_now=f"{t_now:.4f}", window_s=f"{window_s:g}")
    row_h = (f.bottom - f.top) / 6.0
    n_bars = 0
    for pair in (1, 2):  # thin lines between fore, middle and hind
        y = f.top + 2 * pair * row_h
        out.append(
            f'<line x1="{LEFT}" y1="{y:.1f}" x2="{f.right}" y2="{y:.1f}" stroke="#ccc" '
            'stroke-width="0.5"/>'
        )
    for leg, legbars in enumerate(bars):
        y = f.top + leg * row_h
        out.append(
            f'<text x="{LEFT - 3}" y="{y + row_h * 0.7:.1f}" {FONT} text-anchor="end" '
            f'fill="{PAIR_COLOURS[leg // 2]}">{leg + 1} {LEG_ORDER[leg]}</text>'
        )
        for a, b in legbars:
            a, b = max(a, t0), min(b, t1)
            if b <= a:
                continue
            n_bars += 1
            out.append(
                f'<rect class="stance" data-leg="{LEG_ORDER[leg]}" x="{f.x(a):.2f}" '
                f'y="{y + row_h * 0.15:.1f}" width="{f.x(b) - f.x(a):.2f}" '
                f'height="{row_h * 0.7:.1f}" fill="{LEG_COLOURS[leg]}"/>'
            )
    fmt = "{:.2f}" if window_s < 1.5 else "{:.1f}"
    out += x_ticks(f, time_ticks(t0, t1), fmt)
    out.append(time_axis_word(f))
    out.append(f"<!-- {n_bars} bars --></svg>")
    return "\n".join(out)

"""The Delta31 history: Delta31 at each leg-1 touchdown over time, the thin vertical marks
where the conditions changed (with what changed, laid out so labels never print over each
other), and a finished job's run beside the live walk.

Its own module because the marks' label layout is the one piece of chart logic with state
(rows taken, labels folded into "+n"); the axes and dots are web/svg.py's.
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence

from sim_core.contract import TWO_PI
from web.legend_svg import label_width
from web.record import CoreEvents, Mark
from web.style import JOB_COLOUR, MARK_COLOUR
from web.svg import (
    CHAR_W,
    FONT,
    LEFT,
    LINE,
    MAX_DRAWN,
    Frame,
    dots,
    open_svg,
    panel_frame,
    reference_lines,
    time_axis_word,
    time_ticks,
    time_window,
    x_ticks,
    y_angle_axis,
)

MARK_ROWS = 3  # label heights in turn
FOLD_ROOM = " +99"  # room kept after each label for the count of marks folded into it
__all__ = ["CHAR_W", "d31_svg"]


def d31_svg(
    events: CoreEvents,
    t_now: float,
    window_s: float | None,
    gait: str,
    marks: Sequence[Mark] = (),
    job: tuple[str, Sequence[tuple[float, float]]] | None = None,
) -> str:
    """Delta31 at each leg-1 touchdown, (time_s, Delta31) as `Simulation.d31_events` has them,
    over the last `window_s` (None: the whole run), with the two gaits' lines; beyond MAX_DRAWN
    points every k-th is drawn (the title says so)."""
    whole = window_s is None
    span = max(t_now, 1.0) if window_s is None else window_s
    t0, t1 = time_window(t_now, span)
    shown = [(t, d) for t, d in events if t0 <= t <= t1 and math.isfinite(d)]
    k = max(1, math.ceil(len(shown) / MAX_DRAWN))
    if k > 1:
        shown = shown[::k]
    what = "whole run" if whole else f"last {span:g} s"
    thin = f" (1 in {k} drawn)" if k > 1 else ""
    title = f"Δ31, {what}{thin} — gait: {gait}"
    f = panel_frame(title, t0, t1, 0.0, TWO_PI, below=LINE)  # a row for the axis word
    out = open_svg(
        "d31",
        title,
        f,
        gait=gait,
        n_events=str(len(events)),
        t0=f"{t0:.3f}",
    )
    out += y_angle_axis(f) + reference_lines(f)
    pts = [(f.x(t), f.y(d)) for t, d in shown]
    # Delta31 is an angle: a step across 0 = 2 pi is not a swing through pi, so the line breaks
    segments: list[list[tuple[float, float]]] = []
    for i, p in enumerate(pts):
        if i == 0 or abs(shown[i][1] - shown[i - 1][1]) > math.pi:
            segments.append([])
        segments[-1].append(p)
    for seg in segments:
        if len(seg) >= 2:
            path = " ".join(f"{x:.1f},{y:.1f}" for x, y in seg)
            out.append(f'<polyline points="{path}" fill="none" stroke="#444" stroke-width="0.6"/>')
    if job is not None:  # a finished job's run, on the same time axis (both start at 0)
        name, series = job
        xy = [(f.x(t), f.y(d)) for t, d in series if t0 <= t <= t1 and math.isfinite(d)]
        out.append(dots(xy[-MAX_DRAWN:], 1.2, JOB_COLOUR, 0.8, "job"))
        out.append(
            f'<text class="job" x="{LEFT + 3}" y="{f.bottom - 4}" {FONT} fill="{JOB_COLOUR}">'
            f"● job {html.escape(name)}</text>"
        )
    out.append(dots(pts, 1.6 if len(pts) < 300 else 1.0, "#222"))
    out += _marks(f, [m for m in marks if t0 <= m.time_s <= t1])
    fmt = "{:.0f}" if span >= 4 else "{:.1f}"
    out += x_ticks(f, time_ticks(t0, t1), fmt)
    out.append(time_axis_word(f))
    out.append("</svg>")
    return "\n".join(out)


def _placed(f: Frame, x: float, label: str) -> tuple[float, str, str]:
    """Where a mark's label goes: (its left edge, anchor, the words): right of its line, or
    left of it at the plot's right edge, with room for a "+n" that later marks may add; a
    label too long for either side is cut to the wider one ("…"; the line keeps the whole)."""
    width = label_width(label + FOLD_ROOM)
    room_right, room_left = f.right - x - 2, x - 4
    if width > max(room_right, room_left):
        keep = int(max(room_right, room_left) / CHAR_W) - len(FOLD_ROOM) - 1
        label = label[: max(0, keep)] + "…"
        width = label_width(label + FOLD_ROOM)
    if width <= room_right:
        return x + 2, "start", label
    return x - 2 - width, "end", label


def _marks(f: Frame, marks: Sequence[Mark]) -> list[str]:
    """A thin vertical line where the conditions changed, with what changed beside it.

    Each label takes the first of three rows where it does not print over the previous label
    there (`_placed`); where none is free (a short ramp's phases on a long history) the line
    keeps its words as a tooltip and in `data-label`, and the last label printed counts the
    marks it stands for ("+2").
    """
    out: list[str] = []
    row_end = [-math.inf] * MARK_ROWS
    last_text: int | None = None  # index in `out` of the latest label printed
    extra = 0
    for m in marks:
        x = f.x(m.time_s)
        label = html.escape(m.label)
        out.append(
            f'<line class="mark" data-label="{label}" x1="{x:.1f}" y1="{f.top:g}" '
            f'x2="{x:.1f}" y2="{f.bottom}" stroke="{MARK_COLOUR}" stroke-width="0.6" '
            f'stroke-dasharray="2 2"><title>{label}</title></line>'
        )
        left, anchor, words = _placed(f, x, m.label)
        row = next((r for r in range(MARK_ROWS) if left >= row_end[r]), None)
        if row is None:
            extra += 1
            continue
        if last_text is not None and extra:
            out[last_text] = out[last_text].replace("</text>", f" +{extra}</text>")
        extra = 0
        row_end[row] = left + label_width(words + FOLD_ROOM) + 4
        tx = x + 2 if anchor == "start" else x - 2
        out.append(
            f'<text class="mark" x="{tx:.1f}" y="{f.top + 9 + 9 * row:g}" '
            f'text-anchor="{anchor}" {FONT} fill="{MARK_COLOUR}">{html.escape(words)}</text>'
        )
        last_text = len(out) - 1
    if last_text is not None and extra:
        out[last_text] = out[last_text].replace("</text>", f" +{extra}</text>")
    return out

"""Delta31 against a parameter: the bifurcation panel (the finder's states over beta, this
session's trail, a beta ramp's path and the live point) and the ramp panel (Delta31 against
whatever the latest ramp drives).

One module because both draw a ramp's path the same way (`_ramp_lines`: a line per direction,
broken where Delta31 wraps); the gait and ramp colours are web/style.py's.
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence

from sim_core.contract import TWO_PI
from web.bifurcation import FinderPoints
from web.legend_svg import Entry, legend, legend_lines, rows_height
from web.paper_svg import RANGES_ENTRY, paper_ranges, paper_transitions, transitions_entry
from web.record import D31Event
from web.style import GAIT_COLOURS, RAMP_COLOURS
from web.svg import (
    Frame,
    dots,
    open_svg,
    panel_frame,
    plot_note,
    reference_lines,
    x_ticks,
    y_angle_axis,
)


def _marker(kind: str, x: float, y: float, colour: str) -> str:
    if kind == "stable":
        return (
            f'<circle class="stable" cx="{x:.1f}" cy="{y:.1f}" r="2.4" fill="{colour}" '
            'stroke="#333" stroke-width="0.3"/>'
        )
    if kind == "unstable":
        return (
            f'<circle class="unstable" cx="{x:.1f}" cy="{y:.1f}" r="2.4" fill="#fff" '
            'stroke="#333" stroke-width="0.8"/>'
        )
    if kind == "one-sided":
        return (
            f'<circle class="one-sided" cx="{x:.1f}" cy="{y:.1f}" r="2.0" fill="#bbb" '
            'stroke="#555" stroke-width="0.5"/>'
        )
    if kind == "ghost":
        d = 2.2
        return (
            f'<path class="ghost" d="M{x - d:.1f},{y - d:.1f}L{x + d:.1f},{y + d:.1f}'
            f'M{x - d:.1f},{y + d:.1f}L{x + d:.1f},{y - d:.1f}" stroke="#555" '
            'stroke-width="0.8"/>'
        )
    d = 1.8  # unsettled: a small grey triangle
    return (
        f'<path class="unsettled" d="M{x:.1f},{y - d:.1f}L{x + d:.1f},{y + d:.1f}'
        f'L{x - d:.1f},{y + d:.1f}Z" fill="#aaa"/>'
    )


def bifurcation_svg(
    finder: FinderPoints | None,
    note: str,
    trail: Sequence[D31Event],
    live: tuple[float, float | None],
    beta_range: tuple[float, float],
    ramp_path: Sequence[D31Event] = (),
    *,
    conditions: str = "",  # the ground, mass and slope of what is drawn: ends the title
) -> str:
    """The finder's states over beta (stable filled by gait, unstable open, one-sided grey,
    ghosts x, unsettled finals grey triangles), this session's trail, the path of a beta ramp
    (a line per direction, drawn as it goes) and the live point (red ring)."""
    lo, hi = beta_range
    pts = finder or FinderPoints()
    states: list[Entry] = [(f"● {g}", c) for g, c in GAIT_COLOURS.items()]
    states += [("○ unstable", "#333"), ("● one-sided", "#999"), ("× ghost", "#555"),
               ("▲ not settled", "#999"), ("○ now", "#e00"), ("· this run", "#666")]  # fmt: skip
    rows = [states]  # one row, wrapped where the width ends; the ramp's and the paper's apart
    if any(e.at.ramp for e in ramp_path):
        rows.append([(f"— ramp β {d}", RAMP_COLOURS[d]) for d in ("down", "up")])
    rows.append([RANGES_ENTRY, transitions_entry()])
    lines = legend_lines(rows)
    title = "Bifurcation: Δ31 vs β (finder; this run)" + (f" — {conditions}" if conditions else "")
    f = panel_frame(title, lo, hi, 0.0, TWO_PI, below=rows_height(len(lines)))
    out = open_svg("bifurcation", title, f, n_cached=str(len(pts)))
    out += y_angle_axis(f) + reference_lines(f)
    out += paper_ranges(f, GAIT_COLOURS) + paper_transitions(f, label=True)
    kinds = (("unsettled", pts.unsettled), ("ghost", pts.ghosts), ("unstable", pts.unstable),
             ("one-sided", pts.one_sided))  # fmt: skip
    for kind, points in kinds:  # drawn in this order: the stable points go on top
        out.extend(_marker(kind, f.x(b), f.y(d), "") for b, d in points if lo <= b <= hi)
    for b, d, gait in pts.stable:
        if lo <= b <= hi:
            colour = GAIT_COLOURS.get(gait, GAIT_COLOURS["other"])
            out.append(_marker("stable", f.x(b), f.y(d), colour))
    trail_xy = [(f.x(e.at.beta), f.y(e.d31)) for e in trail if lo <= e.at.beta <= hi]
    out.append(dots(trail_xy, 1.0, "#000", 0.35, "trail"))
    out += _ramp_lines(f, ramp_path, lo, hi)
    beta, d31 = live
    if d31 is not None:
        out.append(
            f'<circle class="live" cx="{f.x(min(hi, max(lo, beta))):.1f}" cy="{f.y(d31):.1f}" '
            'r="3.5" fill="none" stroke="#e00" stroke-width="1.5"/>'
        )
    if note:
        out.append(plot_note(f, note))
    ticks = [0.55, 0.60, 0.65, 0.70, 0.75, 0.80]
    out += x_ticks(f, [t for t in ticks if lo <= t <= hi], "{:.2f}")
    out += legend(f, lines)
    out.append("</svg>")
    return "\n".join(out)


def _ramp_lines(
    f: Frame, path: Sequence[D31Event], lo: float, hi: float, param: str = "beta"
) -> list[str]:
    """The ramp's (parameter, Delta31) path: one polyline per stretch of one direction, broken
    where Delta31 wraps across 0 = 2 pi (a wrap is not a swing through pi)."""
    out: list[str] = []
    segments: list[tuple[str, list[D31Event]]] = []

    def at(e: D31Event) -> float:
        return float(getattr(e.at, param))

    for i, e in enumerate(path):
        if not e.at.ramp or not lo <= at(e) <= hi:
            continue
        prev = path[i - 1] if i > 0 else None
        if (
            not segments
            or prev is None
            or segments[-1][0] != e.at.ramp
            or segments[-1][1][-1] is not prev
            or abs(e.d31 - prev.d31) > math.pi
        ):
            segments.append((e.at.ramp, []))
        segments[-1][1].append(e)
    for direction, seg in segments:
        colour = RAMP_COLOURS.get(direction, "#444")
        pts = " ".join(f"{f.x(at(e)):.1f},{f.y(e.d31):.1f}" for e in seg)
        if len(seg) >= 2:
            out.append(
                f'<polyline class="ramp" data-direction="{html.escape(direction)}" '
                f'points="{pts}" fill="none" stroke="{colour}" stroke-width="1.6"/>'
            )
        else:
            e = seg[0]
            out.append(
                f'<circle class="ramp" cx="{f.x(at(e)):.1f}" cy="{f.y(e.d31):.1f}" r="1" '
                f'fill="{colour}"/>'
            )
    return out


def ramp_path_svg(
    path: Sequence[D31Event], param: str, axis_label: str, value_range: tuple[float, float]
) -> str:
    """Delta31 against the ramped parameter during the latest ramp (Fig. 6a's own axes for a
    beta ramp; the same for body mass or slope), a line per direction as it goes."""
    lo, hi = value_range
    rows: list[list[Entry]] = [[(f"— {d}", RAMP_COLOURS[d]) for d in ("down", "up")]]
    if param == "beta":  # Fig. 6a's own axes: the paper's transitions, in the ramp's colours
        rows[0].append(transitions_entry("paper, Fig. 6a"))
    lines = legend_lines(rows)
    title = f"Ramp: Δ31 vs {axis_label}"
    f = panel_frame(title, lo, hi, 0.0, TWO_PI, below=rows_height(len(lines)))
    out = open_svg("ramp-path", title, f, param=param, n_events=str(len(path)))
    out += y_angle_axis(f) + reference_lines(f)
    if param == "beta":
        out += paper_transitions(f, RAMP_COLOURS)
    out += _ramp_lines(f, path, lo, hi, param)
    span = hi - lo
    step = next(s for s in (0.01, 0.02, 0.05, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0) if span / s <= 6)
    ticks = [step * k for k in range(math.ceil(lo / step), math.floor(hi / step) + 1)]
    out += x_ticks(f, ticks, "{:.2f}" if step < 0.1 else "{:g}")
    out += legend(f, lines)
    out.append("</svg>")
    return "\n".join(out)

"""The return map: Delta31(n) against Delta31(n + lag) of the current run, newer pairs darker.

Its own module because it is the one square panel (its own viewBox, drawn narrower so that its
type is the others' size) and the one scatter coloured by age; frame, dots and the angle axis
are web/svg.py's.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from sim_core.contract import TWO_PI
from web.svg import FONT, MAX_DRAWN, Frame, dots, open_svg, y_angle_axis

RM = 190  # the return map's square viewBox (drawn at RM / W of the panel's width)
RM_TITLE_H = 10.0  # room under the ticks for the x axis' title
RECENCY_SHADES = 6  # the return map's age groups, each one path of one opacity


def return_map_svg(pairs: Sequence[tuple[float, float]], lag: int = 4) -> str:
    """Delta31(n) -> Delta31(n + lag) of the current run: a fixed point sits on the diagonal;
    newer pairs are darker."""
    f = Frame(0.0, TWO_PI, 0.0, TWO_PI, w=RM, h=RM, legend_h=RM_TITLE_H)
    out = open_svg(
        "return-map",
        f"Return map: Δ31(n) → Δ31(n+{lag})",
        w=RM,
        h=RM,
        legend_h=RM_TITLE_H,
        n_pairs=str(len(pairs)),
    )
    out += y_angle_axis(f)
    mid_x, mid_y = (f.x(0.0) + f.x(TWO_PI)) / 2, (f.y(0.0) + f.y(TWO_PI)) / 2
    out.append(
        f'<text class="axis-title" x="{mid_x:.1f}" y="{f.bottom + 21}" {FONT} fill="#666" '
        f'text-anchor="middle">Δ31(n) (rad)</text>'
    )
    out.append(
        f'<text class="axis-title" x="8" y="{mid_y:.1f}" {FONT} fill="#666" text-anchor="middle" '
        f'transform="rotate(-90 8 {mid_y:.1f})">Δ31(n+{lag}) (rad)</text>'
    )
    out.append(
        f'<line x1="{f.x(0):.1f}" y1="{f.y(0):.1f}" x2="{f.x(TWO_PI):.1f}" '
        f'y2="{f.y(TWO_PI):.1f}" stroke="#999" stroke-width="0.6" stroke-dasharray="3 2"/>'
    )
    shown = [(f.x(x), f.y(y)) for x, y in list(pairs)[-MAX_DRAWN:]]
    # newer darker: RECENCY_SHADES groups of equal size, oldest faintest
    for k, group in enumerate(np.array_split(np.arange(len(shown)), RECENCY_SHADES)):
        if len(group):
            pts = [shown[i] for i in group]
            out.append(dots(pts, 1.2, "#222", 0.15 + 0.85 * (k + 1) / RECENCY_SHADES))
    for v, label in ((0.0, "0"), (TWO_PI / 3, "2π/3"), (math.pi, "π"), (TWO_PI, "2π")):
        out.append(
            f'<text x="{f.x(v):.1f}" y="{f.bottom + 11}" {FONT} text-anchor="middle">{label}</text>'
        )
    out.append("</svg>")
    return "\n".join(out)

"""The gait atlas: a grid of cells coloured by region (beta across, body mass or slope up)
with the live point and the paper's transition betas; a note when there is no atlas for the
axis.

The rows are of equal height, one per value of the atlas, each with its tick: the values are
not evenly spaced (1, 1.5, ... 4, 6, 8 g), and on a linear axis the light rows were a few
pixels tall and their ticks printed over each other, so every other row went unlabelled. The
live point sits between the rows of the two values around it, in proportion.

Its own module because it reads a whole `SurfaceAtlas` (regions, unresolved zeros) rather than
points; its region colours extend the gait colours (web/style.py).
"""

from __future__ import annotations

import bisect
import html
import math
from collections.abc import Sequence

from sim_core.contract import SurfaceAtlas
from web.legend_svg import Entry, legend, legend_lines, rows_height
from web.paper_svg import paper_transitions, transitions_entry
from web.style import GAIT_COLOURS
from web.svg import FONT, LEFT, LINE, Frame, cell_edges, open_svg, panel_frame, plot_note, x_ticks

# The atlas's regions (`surface_atlas.region`): both gaits purple, one gait its colour
REGION_COLOURS = {
    "both": "#9467bd",
    "tripod only": GAIT_COLOURS["tripod"],
    "metachronal only": GAIT_COLOURS["metachronal"],
    "other states": "#c7c7c7",
    "none": "#f4f4f4",
}
_REGIONS = [(f"■ {r}", c if r != "none" else "#999") for r, c in REGION_COLOURS.items()]
LEGEND: list[list[Entry]] = [  # one row, wrapped where the width ends
    [*_REGIONS, ("? unresolved", "#555"), ("○ now", "#e00"), transitions_entry()]
]


def row_position(values: Sequence[float], v: float) -> float:
    """Where `v` sits on the row axis: row k's centre is k + 0.5 for the k-th smallest value,
    between two values in proportion, clamped to the outer rows' edges."""
    vs = sorted(values)
    if v < vs[0] or v > vs[-1]:
        return 0.0 if v < vs[0] else float(len(vs))
    if v == vs[-1]:
        return len(vs) - 0.5
    k = bisect.bisect_right(vs, v) - 1
    return k + 0.5 + (v - vs[k]) / (vs[k + 1] - vs[k])


def _row_ticks(f: Frame, values: Sequence[float]) -> list[str]:
    """A tick label on every row while rows are a line of text tall; on every k-th when an
    atlas has so many rows that they are not."""
    n = len(values)
    step = max(1, math.ceil(LINE / ((f.bottom - f.top) / n)))
    return [
        f'<text x="{LEFT - 3}" y="{f.y(k + 0.5) + 3:.1f}" {FONT} text-anchor="end">{v:g}</text>'
        for k, v in enumerate(sorted(values))
        if k % step == 0
    ]


def atlas_svg(
    atlas: SurfaceAtlas | None,
    note: str,
    axis: str,
    axis_label: str,
    live: tuple[float, float] | None,  # None: the walk is not under this atlas's conditions
    beta_range: tuple[float, float],
    *,
    conditions: str = "",  # the ground and the value held fixed: ends the title
) -> str:
    """The gait atlas as a grid of cells coloured by region (beta across, a row per mass or
    slope), with the live (beta, value) point as a red ring and the paper's transition betas
    as dashed verticals; `note` when there is no atlas."""
    title = f"Atlas: {axis_label} vs β" + (f" — {conditions}" if conditions else "")
    lines = legend_lines(LEGEND)
    below = rows_height(len(lines))
    if atlas is None or not atlas.betas or not atlas.values:
        f = panel_frame(title, *beta_range, 0.0, 1.0, below=below)
        out = open_svg("atlas", title, f, axis=axis, n_cells="0")
        out.append(plot_note(f, note or f"no atlas over {axis}"))
        out.append("</svg>")
        return "\n".join(out)
    order_b = sorted(range(len(atlas.betas)), key=lambda j: atlas.betas[j])
    order_v = sorted(range(len(atlas.values)), key=lambda i: atlas.values[i])
    be = cell_edges([atlas.betas[j] for j in order_b])
    nb, nv = len(atlas.betas), len(atlas.values)
    f = panel_frame(title, be[0], be[-1], 0.0, float(nv), below=below)
    out = open_svg("atlas", title, f, axis=axis, n_cells=str(nb * nv))
    for vi, i in enumerate(order_v):
        for bj, j in enumerate(order_b):
            region = atlas.regions[i][j]
            # faint and marked "?" where the region may hide a gait (`AtlasPoint.undecided`):
            # a walk that should decide it did not settle, or, in an atlas written before the
            # walks, a zero or near-zero band in the window stayed unresolved
            pt = atlas.points[i * nb + j]
            unresolved = pt.undecided
            why = "unresolved: a walk did not settle" if pt.checked else "unresolved zeros here"
            x0, x1 = f.x(be[bj]), f.x(be[bj + 1])
            y0, y1 = f.y(vi + 1), f.y(vi)
            out.append(
                f'<rect class="cell" data-region="{html.escape(region)}" '
                f'data-unresolved="{str(unresolved).lower()}" x="{x0:.1f}" '
                f'y="{y0:.1f}" width="{x1 - x0:.1f}" height="{y1 - y0:.1f}" '
                f'fill="{REGION_COLOURS.get(region, "#fff")}" '
                f'fill-opacity="{0.5 if unresolved else 1}" stroke="#fff" stroke-width="0.5">'
                f"<title>β {atlas.betas[j]:g}, {html.escape(axis_label)} {atlas.values[i]:g}: "
                f"{html.escape(region)}{f' ({why})' if unresolved else ''}"
                "</title></rect>"
            )
            if unresolved:
                out.append(
                    f'<text class="unresolved" x="{0.5 * (x0 + x1):.1f}" '
                    f'y="{0.5 * (y0 + y1) + 3:.1f}" {FONT} text-anchor="middle">?</text>'
                )
    out += paper_transitions(f)
    values = atlas.values
    if live is not None:
        beta, value = live
        inside = be[0] <= beta <= be[-1] and min(values) <= value <= max(values)
        cx = f.x(min(be[-1], max(be[0], beta)))
        cy = f.y(row_position(values, value))
        out.append(
            f'<circle class="live" data-inside="{str(inside).lower()}" cx="{cx:.1f}" '
            f'cy="{cy:.1f}" r="3.5" fill="none" stroke="#e00" stroke-width="1.5"/>'
        )
    step = max(1, math.ceil(nb / 6))
    out += x_ticks(f, [atlas.betas[j] for j in order_b][::step], "{:.3g}")
    out += _row_ticks(f, values)
    out += legend(f, lines)
    out.append("</svg>")
    return "\n".join(out)

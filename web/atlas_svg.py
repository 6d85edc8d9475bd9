"""The gait atlas: a grid of cells coloured by region (beta across, body mass or slope up)
with the live point; a note when there is no atlas for the axis.

Its own module because it reads a whole `SurfaceAtlas` (regions, unresolved zeros) rather than
points; its region colours extend the bifurcation panel's gait colours.
"""

from __future__ import annotations

import html
import math

from sim_core.contract import SurfaceAtlas
from web.bifurcation_svg import GAIT_COLOURS
from web.svg import (
    BIF_H,
    FONT,
    LEFT,
    LEGEND_H,
    Frame,
    cell_edges,
    legend,
    open_svg,
    plot_note,
    x_ticks,
)

# The atlas's regions (`surface_atlas.region`): both gaits purple, one gait its colour
REGION_COLOURS = {
    "both": "#9467bd",
    "tripod only": GAIT_COLOURS["tripod"],
    "metachronal only": GAIT_COLOURS["metachronal"],
    "other states": "#c7c7c7",
    "none": "#f4f4f4",
}


def atlas_svg(
    atlas: SurfaceAtlas | None,
    note: str,
    axis: str,
    axis_label: str,
    live: tuple[float, float],
    beta_range: tuple[float, float],
) -> str:
    """The gait atlas as a grid of cells coloured by region (beta across, mass or slope up),
    with the live (beta, value) point as a red ring; `note` when there is no atlas."""
    title = f"Atlas: {axis_label} vs β"
    if atlas is None or not atlas.betas or not atlas.values:
        lo, hi = beta_range
        f = Frame(lo, hi, 0.0, 1.0, h=BIF_H, legend_h=LEGEND_H)
        out = open_svg("atlas", title, h=BIF_H, legend_h=LEGEND_H, axis=axis, n_cells="0")
        out.append(plot_note(f, note or f"no atlas over {axis}"))
        out.append("</svg>")
        return "\n".join(out)
    order_b = sorted(range(len(atlas.betas)), key=lambda j: atlas.betas[j])
    order_v = sorted(range(len(atlas.values)), key=lambda i: atlas.values[i])
    be = cell_edges([atlas.betas[j] for j in order_b])
    ve = cell_edges([atlas.values[i] for i in order_v])
    f = Frame(be[0], be[-1], ve[0], ve[-1], h=BIF_H, legend_h=LEGEND_H)
    out = open_svg(
        "atlas",
        title,
        h=BIF_H,
        legend_h=LEGEND_H,
        axis=axis,
        n_cells=str(len(atlas.betas) * len(atlas.values)),
    )
    nb = len(atlas.betas)
    for vi, i in enumerate(order_v):
        for bj, j in enumerate(order_b):
            region = atlas.regions[i][j]
            # faint where a zero or near-zero band in the window stayed unresolved: the region
            # may hide a gait (the tripod's narrow pair, most often)
            unresolved = atlas.points[i * nb + j].unresolved > 0
            x0, x1 = f.x(be[bj]), f.x(be[bj + 1])
            y0, y1 = f.y(ve[vi + 1]), f.y(ve[vi])
            out.append(
                f'<rect class="cell" data-region="{html.escape(region)}" '
                f'data-unresolved="{str(unresolved).lower()}" x="{x0:.1f}" '
                f'y="{y0:.1f}" width="{x1 - x0:.1f}" height="{y1 - y0:.1f}" '
                f'fill="{REGION_COLOURS.get(region, "#fff")}" '
                f'fill-opacity="{0.5 if unresolved else 1}" stroke="#fff" stroke-width="0.5">'
                f"<title>β {atlas.betas[j]:g}, {html.escape(axis_label)} {atlas.values[i]:g}: "
                f"{html.escape(region)}{' (unresolved zeros here)' if unresolved else ''}"
                "</title></rect>"
            )
    beta, value = live
    inside = be[0] <= beta <= be[-1] and ve[0] <= value <= ve[-1]
    cx = f.x(min(be[-1], max(be[0], beta)))
    cy = f.y(min(ve[-1], max(ve[0], value)))
    out.append(
        f'<circle class="live" data-inside="{str(inside).lower()}" cx="{cx:.1f}" cy="{cy:.1f}" '
        'r="3.5" fill="none" stroke="#e00" stroke-width="1.5"/>'
    )
    step = max(1, math.ceil(nb / 6))
    out += x_ticks(f, [atlas.betas[j] for j in order_b][::step], "{:.3g}")
    nv = len(atlas.values)
    vstep = max(1, math.ceil(nv / 6))
    for i in order_v[::vstep]:
        v = atlas.values[i]
        out.append(
            f'<text x="{LEFT - 3}" y="{f.y(v) + 3:.1f}" {FONT} text-anchor="end">{v:g}</text>'
        )
    regions = list(REGION_COLOURS.items())
    rows = [
        [(f"■ {r}", c if r != "none" else "#999") for r, c in regions[:3]],
        [(f"■ {r}", c if r != "none" else "#999") for r, c in regions[3:]]
        + [("faint: unresolved", "#999"), ("◯ now", "#e00")],
    ]
    out += legend(f, rows)
    out.append("</svg>")
    return "\n".join(out)

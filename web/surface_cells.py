"""The drift surface's backdrop and colour scale (web/surface_svg.py draws the rest).

The first pass's usable probes on its grid as <rect>s (a run of equal colour up a column is one
rect), coloured on a symmetric diverging log scale: red where Delta31 grows, blue where it
falls, white near zero; and the scale's swatches under the legend. Its own module because the
scale and the grid bookkeeping (which probe is which cell, the runs of one colour) are a
concern of their own, apart from the zeros, links, bands and folds drawn over them.
"""

from __future__ import annotations

import math

from sim_core.contract import DriftSurface
from web.legend_svg import LEGEND_X, label_width, row_y
from web.svg import FONT, Frame, cell_edges

D31_RANGE = (1.3, 3.5)  # rad: the surface's grid, not 0-2 pi
GROWS_RGB = (178, 24, 43)  # red: Delta31 grows
FALLS_RGB = (33, 102, 172)  # blue: Delta31 falls
NO_DATA = "#ececec"  # behind the cells: an unusable probe leaves this showing
COLOUR_STEPS = 24
SCALE_MRAD = (-100.0, -10.0, 0.0, 10.0, 100.0)  # the colour scale's swatches


def drift_level(drift_rad: float) -> float:
    """The colour scale's coordinate: sign * log10(1 + |drift in mrad per cycle|)."""
    return math.copysign(math.log10(1.0 + abs(drift_rad) * 1e3), drift_rad)


def drift_colour(level: float, top: float) -> str:
    """White at 0, the full red (level > 0) or blue (< 0) at |level| >= top."""
    # in COLOUR_STEPS steps per side: no eye tells them apart, and equal neighbours merge
    t = round(min(1.0, abs(level) / top) * COLOUR_STEPS) / COLOUR_STEPS if top > 0 else 0.0
    end = GROWS_RGB if level > 0 else FALLS_RGB
    r, g, b = (round(255 + (c - 255) * t) for c in end)
    return f"#{r:02x}{g:02x}{b:02x}"


def grid_key(v: float) -> float:
    """Grid values as the core rounds them (`sim_core.contract.surface.grid`: 1e-6)."""
    return round(v, 6)


def drift_cells(
    surface: DriftSurface, f: Frame, lo: float, hi: float
) -> tuple[list[str], list[str], float, int]:
    """The backdrop over the grid's extent, the usable first-pass probes as rects (a run of
    equal colour up a column one rect), the scale's top level and the number of probes drawn."""
    betas = sorted(surface.betas)
    grid = sorted(surface.config.d31_grid or {grid_key(p.pin_d31) for p in surface.points})
    col = {grid_key(b): j for j, b in enumerate(betas)}
    row = {grid_key(d): i for i, d in enumerate(grid)}
    be, de = cell_edges(betas), cell_edges(grid)
    y_lo, y_hi = D31_RANGE

    def box(j: int, i0: int, i1: int, j1: int | None = None) -> tuple[float, ...] | None:
        """Columns j..j1 (default j), rows i0..i1 - 1, clipped to the frame."""
        x0, x1 = f.x(max(lo, be[j])), f.x(min(hi, be[j + 1 if j1 is None else j1 + 1]))
        y0, y1 = f.y(min(y_hi, de[i1])), f.y(max(y_lo, de[i0]))
        return (x0, y0, x1 - x0, y1 - y0) if x1 > x0 and y1 > y0 else None

    drawn = [
        (col[grid_key(p.beta)], row[grid_key(p.pin_d31)], drift_level(p.drift))
        for p in surface.points
        if p.usable
        and p.drift is not None
        and math.isfinite(p.drift)
        and grid_key(p.beta) in col
        and grid_key(p.pin_d31) in row
    ]
    top = max((abs(v) for _, _, v in drawn), default=1.0)
    backdrop = []
    whole = box(0, 0, len(grid), len(betas) - 1)
    if whole is not None:
        x, y, w, h = whole
        backdrop.append(
            f'<rect class="no-data" x="{x:.1f}" y="{y:.1f}" width="{w:.1f}" height="{h:.1f}" '
            f'fill="{NO_DATA}"/>'
        )
    # one rect per run of equal colour up a column (the panel is resent when the live point
    # moves: ~1 100 single cells were 95 kB, the runs about half that)
    runs: list[tuple[int, int, int, str]] = []  # column, first row, last row, colour
    for j, i, v in sorted(drawn):
        colour = drift_colour(v, top)
        if runs and runs[-1][0] == j and runs[-1][2] == i - 1 and runs[-1][3] == colour:
            runs[-1] = (j, runs[-1][1], i, colour)
        else:
            runs.append((j, i, i, colour))
    out = []
    for j, i0, i1, colour in runs:
        b = box(j, i0, i1 + 1)
        if b is None:
            continue
        x, y, w, h = b
        # a hair wider and taller, so no anti-aliasing seam shows between neighbours
        out.append(
            f'<rect x="{x:.1f}" y="{y:.1f}" width="{w + 0.3:.1f}" height="{h + 0.3:.1f}" '
            f'fill="{colour}"/>'
        )
    n_cells = len(drawn)
    return backdrop, out, top, n_cells


def scale_row(f: Frame, top: float, row: int) -> list[str]:
    """The colour scale on line `row` under the ticks (after the legend's lines, as laid out):
    'drift per cycle, mrad' and a swatch per value."""
    y = row_y(f, row)
    words = "drift per cycle, mrad:"
    out = [f'<text x="{LEGEND_X:g}" y="{y:.0f}" {FONT} fill="#666">{words}</text>']
    x = LEGEND_X + label_width(words) + 4
    for v in SCALE_MRAD:
        colour = drift_colour(drift_level(v * 1e-3), top)
        label = f"{v:g}".replace("-", "−")  # red (growing) needs no "+": the width does
        out.append(
            f'<rect class="swatch" x="{x:.1f}" y="{y - 6:.0f}" width="7" height="7" '
            f'fill="{colour}" stroke="#999" stroke-width="0.3"/>'
        )
        out.append(f'<text x="{x + 9:.1f}" y="{y:.0f}" {FONT} fill="#333">{label}</text>')
        x += 9 + label_width(label) + 4
    return out

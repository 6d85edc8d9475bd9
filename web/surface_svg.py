"""The drift surface panel: the core's `DriftSurface` (`insect-gait reproduce`) as SVG.

A heat map of the first pass's drift of Delta31 per gait cycle over (beta, held Delta31 = D):
the usable probes on the first-pass grid as <rect>s (refinement probes lie off it and are not
cells; a run of equal colour up a column is one rect), coloured on a symmetric diverging
scale: red where Delta31 grows, blue where it falls, white near zero. Over it the zeros, the
gaits: stable (drift falls through zero as Delta31 rises) filled black, unstable open,
unresolved ones fainter; a zero linked to the nearest zero of its kind at the next grid beta
(within the core's `link_tol_rad`) by a solid (stable) or dashed (unstable) line; near-zero
bands as short grey bars, folds as small x, and the live (beta, Delta31) point as the
bifurcation panel's red ring. Pure, like web/svg.py; the cells and their colour scale are
web/surface_cells.py's.
"""

from __future__ import annotations

import html
import itertools
from collections.abc import Sequence
from typing import Protocol

from sim_core.contract import DriftSurface
from web.legend_svg import Entry, legend, legend_lines, rows_height
from web.paper_svg import paper_transitions, transitions_entry
from web.surface_cells import D31_RANGE, drift_cells, grid_key, scale_row
from web.svg import (
    FONT,
    LEFT,
    open_svg,
    panel_frame,
    plot_note,
    reference_lines,
    x_ticks,
)

D31_TICKS = (1.5, 2.0, 2.5, 3.0, 3.5)
BETA_TICKS = (0.55, 0.60, 0.65, 0.70, 0.75, 0.80)
LEGEND: list[list[Entry]] = [  # one row, wrapped where the width ends
    [("● stable zero", "#000"), ("○ unstable zero", "#000"), ("faint: not resolved", "#888"),
     ("| near zero", "#777"), ("× fold", "#333"), ("■ not usable", "#bbb"), ("○ now", "#e00"),
     transitions_entry()],
]  # fmt: skip


class Zero(Protocol):
    """What the panel reads of a `DriftSurface.zeros` item (the contract exports the surface's
    model, not its parts)."""

    @property
    def beta(self) -> float: ...
    @property
    def d31(self) -> float: ...
    @property
    def stable(self) -> bool: ...
    @property
    def resolved(self) -> bool: ...


def _zero_marker(z: Zero, x: float, y: float) -> str:
    kind = "stable" if z.stable else "unstable"
    faint = "" if z.resolved else ' opacity="0.4"'
    fill = 'fill="#000"' if z.stable else 'fill="#fff" stroke="#000" stroke-width="0.8"'
    tip = (
        f"β {z.beta:g}: {kind} zero at Δ31 {z.d31:.3f} rad{'' if z.resolved else ' (not resolved)'}"
    )
    return (
        f'<circle class="zero" data-kind="{kind}" data-resolved="{str(z.resolved).lower()}" '
        f'cx="{x:.1f}" cy="{y:.1f}" r="2" {fill}{faint}><title>{html.escape(tip)}</title>'
        "</circle>"
    )


def _links(zeros: Sequence[Zero], betas: Sequence[float], tol: float) -> list[tuple[Zero, Zero]]:
    """Each zero and the nearest zero of its kind at the next grid beta, within `tol` rad."""
    by: dict[tuple[float, bool], list[Zero]] = {}
    for z in zeros:
        by.setdefault((grid_key(z.beta), z.stable), []).append(z)
    out = []
    order = sorted(betas)
    for b0, b1 in itertools.pairwise(order):
        for stable in (True, False):
            nxt = by.get((grid_key(b1), stable), [])
            for z in by.get((grid_key(b0), stable), []):
                near = min(nxt, key=lambda n: abs(n.d31 - z.d31), default=None)
                if near is not None and abs(near.d31 - z.d31) <= tol:
                    out.append((z, near))
    return out


def surface_svg(
    surface: DriftSurface | None,
    note: str,
    live: tuple[float, float | None],
    beta_range: tuple[float, float],
    *,
    conditions: str = "",
) -> str:
    """The drift surface over (beta, Delta31) with its zeros, bands, folds and the live point;
    `note` (an absent or invalid surface.json) when there is no surface; `conditions` (the
    ground, mass and slope it is of) ends the title."""
    lo, hi = beta_range
    lines = legend_lines(LEGEND)
    title = "Drift surface: drift of Δ31 per cycle" + (f" — {conditions}" if conditions else "")
    # the legend's lines as laid out (a long row wraps), then the colour scale's line
    f = panel_frame(title, lo, hi, *D31_RANGE, below=rows_height(len(lines) + 1))
    if surface is None or not surface.betas or not surface.points:
        out = open_svg("surface", title, f, n_cells="0", n_zeros="0")
        out.append(plot_note(f, note or "the drift surface is empty"))
        out.append("</svg>")
        return "\n".join(out)
    backdrop, cells, top, n_cells = drift_cells(surface, f, lo, hi)
    y_lo, y_hi = D31_RANGE

    def shown(beta: float, d31: float) -> bool:
        return lo <= beta <= hi and y_lo <= d31 <= y_hi

    zeros = [z for z in surface.zeros if shown(z.beta, z.d31)]
    out = open_svg(
        "surface",
        title,
        f,
        n_cells=str(n_cells),
        n_zeros=str(len(zeros)),
        top_mrad=f"{10**top - 1:.0f}",
    )
    out += backdrop + cells
    for v in D31_TICKS:
        out.append(
            f'<text x="{LEFT - 3}" y="{f.y(v) + 3:.1f}" {FONT} text-anchor="end">{v:g}</text>'
        )
    out += reference_lines(f) + paper_transitions(f)
    tol = surface.config.link_tol_rad
    for a, b in _links(zeros, surface.betas, tol):
        dash = "" if a.stable else ' stroke-dasharray="2 1.5"'
        kind = "stable" if a.stable else "unstable"
        out.append(
            f'<line class="link" data-kind="{kind}" x1="{f.x(a.beta):.1f}" y1="{f.y(a.d31):.1f}" '
            f'x2="{f.x(b.beta):.1f}" y2="{f.y(b.d31):.1f}" stroke="#000" '
            f'stroke-width="0.7"{dash}/>'
        )
    for n in surface.near_zeros:
        mid = (n.lo + n.hi) / 2
        if not shown(n.beta, mid):
            continue
        x = f.x(n.beta)
        y0, y1 = f.y(n.hi), f.y(n.lo)
        if y1 - y0 < 4.0:  # a band is a few hundredths of a radian: keep it visible
            c = (y0 + y1) / 2
            y0, y1 = c - 2.0, c + 2.0
        out.append(
            f'<line class="near-zero" x1="{x:.1f}" y1="{y0:.1f}" x2="{x:.1f}" y2="{y1:.1f}" '
            'stroke="#777" stroke-width="1.4"/>'
        )
    for z in zeros:
        out.append(_zero_marker(z, f.x(z.beta), f.y(z.d31)))
    for fold in surface.folds:
        beta = (fold.beta_lo + fold.beta_hi) / 2
        if not shown(beta, fold.d31):
            continue
        x, y, d = f.x(beta), f.y(fold.d31), 1.8
        out.append(
            f'<path class="fold" d="M{x - d:.1f},{y - d:.1f}L{x + d:.1f},{y + d:.1f}'
            f'M{x - d:.1f},{y + d:.1f}L{x + d:.1f},{y - d:.1f}" stroke="#333" '
            'stroke-width="0.8"/>'
        )
    beta, d31 = live
    if d31 is not None:
        inside = shown(beta, d31)
        cx = f.x(min(hi, max(lo, beta)))
        cy = f.y(min(y_hi, max(y_lo, d31)))
        out.append(
            f'<circle class="live" data-inside="{str(inside).lower()}" cx="{cx:.1f}" '
            f'cy="{cy:.1f}" r="3.5" fill="none" stroke="#e00" stroke-width="1.5"/>'
        )
    if note:
        out.append(plot_note(f, note))
    out += x_ticks(f, [t for t in BETA_TICKS if lo <= t <= hi], "{:.2f}")
    out += legend(f, lines)
    out += scale_row(f, top, len(lines))
    out.append("</svg>")
    return "\n".join(out)

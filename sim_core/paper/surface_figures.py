"""Figs. 7 and 8 and the mechanism, drawn from the drift surface (`paper.surface`), with the
reproduction rows they answer and the free runs they are checked against.

- Fig. 8 (`fig8_surface`): the drift per cycle as a heat map over (beta, held Delta31), its
  zeros (stable filled, unstable open) linked into branches (stable solid, unstable dashed),
  near-zero bands, the folds with their resolution, and Fig. 6a's two sweeps on top.
- Fig. 7 (`fig7_surface`): the return maps Delta31 -> Delta31 + 4 d(Delta31) at the map betas,
  and below each the map minus the diagonal (4 d, mrad) with the settled free-run pairs of the
  finder as dots: what is plotted is checked against independent long runs on the same axes.
- The mechanism (`mechanism`): the mean jumps e1, e3, e5 against Delta31 at three betas on
  each ground, with the two timing lines of shared/notes/gait-mechanism.md: L_DW (Delta31 =
  2 pi (1 - beta)) and L_FH (Delta31 = pi beta).

Matplotlib with the Agg backend: files only.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import SymLogNorm

from sim_core.contract.surface import AtlasPoint, DriftSurface, SurfaceZero
from sim_core.contract.values import PaperValues
from sim_core.model.gait import classify_gait
from sim_core.paper.analysis import PAPER_WINDOW, FixedPoint
from sim_core.paper.analysis import stable_ranges as analysis_stable_ranges

MRAD = 1e3
Row = tuple[str, str, str, str]


# --- the reproduction rows ----------------------------------------------------------------------
def window_zeros(surface: DriftSurface, beta: float) -> list[SurfaceZero]:
    lo, hi = PAPER_WINDOW
    return [z for z in surface.zeros_at(beta) if lo <= z.d31 <= hi]


def pattern(zeros: Sequence[SurfaceZero]) -> str:
    """'S U S' in order of Delta31: the paper's Fig. 7 reading (unresolved zeros with '?')."""
    return " ".join(("S" if z.stable else "U") + ("" if z.resolved else "?") for z in zeros)


def stable_ranges(surface: DriftSurface, gait: str) -> list[tuple[float, float]]:
    """The grid's runs of betas with a stable zero of `gait` in the window: the finder's rule
    (`analysis.stable_ranges`) on the surface's zeros (map slope 1 + 4 dd/dDelta31)."""
    betas = sorted(surface.betas)
    fixed = [
        [
            FixedPoint(z.d31, 1.0 + 4.0 * (z.slope or 0.0), z.stable)
            for z in window_zeros(surface, b)
        ]
        for b in betas
    ]
    return analysis_stable_ranges(betas, fixed, gait)


def decided_ranges(cells: Sequence[AtlasPoint], gait: str) -> list[tuple[float, float]]:
    """The same runs of grid betas from cells decided by walks (`surface_walks.walk_cells`):
    their stable states are the surface's stable zeros plus the settled walks' finals."""
    cells = sorted(cells, key=lambda c: c.beta)
    fixed = [[FixedPoint(x, math.nan, True) for x in c.stable] for c in cells]
    return analysis_stable_ranges([c.beta for c in cells], fixed, gait)


def _cell_at(cells: Sequence[AtlasPoint] | None, beta: float) -> AtlasPoint | None:
    return next((c for c in cells or () if abs(c.beta - beta) < 1e-9), None)


def walked_states(cell: AtlasPoint | None) -> list[float]:
    """The stable states only the walks found at a cell (none where the surface saw all)."""
    if cell is None:
        return []
    return [x for x, src in zip(cell.stable, cell.provenance, strict=True) if src == "walk"]


def _b(x: float) -> str:
    return f"{x:.2f}" if round(x, 2) == x else f"{x:.3f}"


def fig7_rows(
    surface: DriftSurface, paper: PaperValues, cells: Sequence[AtlasPoint] | None = None
) -> list[Row]:
    """Fig. 7's patterns as the surface reads them, beside the paper's: the same pattern with
    every zero resolved; where the paper names a gait, every stable zero is of it; where its
    map is bistable (two stable points, no gait named), they are a tripod and a metachronal
    state; a match with a near-zero band in the window (which may hide a narrow pair of zeros)
    is only "partly". With `cells` decided by walks (issue 52, point 1), a stable state only a
    walk found is named and breaks the match (the pattern lacks it)."""
    rows: list[Row] = []
    for beta, pat, gait in paper.fixed_points:
        label = f"Fig. 7: fixed points at β = {beta}"
        want = f"{len(pat.split())} ({pat}{', ' + gait if gait else ''})"
        if not any(abs(b - beta) < 1e-9 for b in surface.betas):
            rows.append((label, want, "not run", "not run"))
            continue
        zs = window_zeros(surface, beta)
        where = ", ".join(
            f"{z.d31:.2f} ({classify_gait(z.d31, beta) if z.stable else 'U'})" for z in zs
        )
        ours = f"{len(zs)} ({pattern(zs) or 'none'}){': ' + where if where else ''}"
        near = [n for n in surface.near_zeros if abs(n.beta - beta) < 1e-9]
        if near:
            ours += "; near-zero bands " + ", ".join(f"{n.lo:.2f}-{n.hi:.2f}" for n in near)
        ok = pattern(zs) == pat and all(z.resolved for z in zs)
        gaits = {classify_gait(z.d31, beta) for z in zs if z.stable}
        if ok and gait is not None:
            ok = gaits == {gait}
        elif ok:  # the paper's bistable map (Fig. 7b): one tripod and one metachronal state
            ok = gaits == {"tripod", "metachronal"}
        lo, hi = PAPER_WINDOW
        hidden = ok and any(lo <= n.lo and n.hi <= hi for n in near)  # may hide a pair of zeros
        cell = _cell_at(cells, beta)
        if cell is not None and cell.checked:
            walked = walked_states(cell)
            if walked:
                ours += "; settled walks add " + ", ".join(
                    f"{x:.2f} ({classify_gait(x, beta)})" for x in walked
                )
            ok = ok and not walked  # a band stays "partly": walks cannot see an unstable zero
        rows.append((label, want, ours, "partly" if hidden else "yes" if ok else "**no**"))
    return rows


def fig8_rows(
    surface: DriftSurface,
    paper: PaperValues,
    beta_tol: float,
    cells: Sequence[AtlasPoint] | None = None,
) -> list[Row]:
    """Fig. 8's stable ranges as the surface reads them (`stable_ranges`), beside the paper's:
    inside the betas the paper's figure spans, one range whose ends are within `beta_tol` of
    the paper's. With `cells` decided by walks (issue 52, point 1) the ranges are theirs
    (`decided_ranges`), and the surface's own are named where they differ."""
    rows: list[Row] = []
    # the paper's Fig. 8 spans these betas: what lies outside it is ours alone, not compared
    span = (min(paper.tripod_stable + paper.metachronal_stable),
            max(paper.tripod_stable + paper.metachronal_stable))  # fmt: skip
    for gait in ("tripod", "metachronal"):
        a, b = paper.tripod_stable if gait == "tripod" else paper.metachronal_stable
        alone = stable_ranges(surface, gait)
        ranges = alone if cells is None else decided_ranges(cells, gait)
        segs = "; ".join(f"{_b(lo)}-{_b(hi)}" for lo, hi in ranges) or "nowhere on the grid"
        if ranges != alone:
            was = "; ".join(f"{_b(lo)}-{_b(hi)}" for lo, hi in alone) or "nowhere"
            segs += f" with settled walks (the surface alone: {was})"
        grid = sorted(surface.betas)
        # the grid's spacing: one step, or the finest and the coarsest where it varies
        steps = sorted({round(y - x, 6) for x, y in itertools.pairwise(grid)})
        ends = dict.fromkeys((steps[0], steps[-1])) if steps else {}
        step = f" by {'-'.join(_b(x) for x in ends)}" if ends else ""
        ours = f"{segs} (grid {_b(grid[0])}-{_b(grid[-1])}{step})"
        ranges = [(max(lo, span[0]), min(hi, span[1])) for lo, hi in ranges]
        ranges = [(lo, hi) for lo, hi in ranges if lo <= hi]
        if (grid[0], grid[-1]) != span:
            ours += f"; compared inside the paper's {_b(span[0])}-{_b(span[1])}"
        ok = len(ranges) == 1 and abs(ranges[0][0] - a) <= beta_tol
        ok = ok and abs(ranges[0][1] - b) <= beta_tol
        rows.append(
            (f"Fig. 8: {gait} stable for β in", f"{_b(a)}-{_b(b)}", ours, "yes" if ok else "**no**")
        )
    return rows


def table_rows(surface: DriftSurface, paper: PaperValues, beta_tol: float) -> list[Row]:
    """Fig. 7's patterns and Fig. 8's stable ranges (`fig7_rows`, `fig8_rows`)."""
    return fig7_rows(surface, paper) + fig8_rows(surface, paper, beta_tol)


# --- Fig. 8 -------------------------------------------------------------------------------------
def _grid(surface: DriftSurface) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(betas, D grid, drift (nD, nb)) of the first pass (NaN where a probe was not used)."""
    betas = np.array(sorted(surface.betas))
    ds = np.array(sorted(surface.config.d31_grid))
    z = np.full((ds.size, betas.size), np.nan)
    bi = {round(b, 6): k for k, b in enumerate(betas)}
    di = {round(d, 6): k for k, d in enumerate(ds)}
    for p in surface.points:
        k, m = bi.get(round(p.beta, 6)), di.get(round(p.pin_d31, 6))
        if k is not None and m is not None and p.usable and p.drift is not None:
            z[m, k] = p.drift * MRAD
    return betas, ds, z


def _edges(x: np.ndarray) -> np.ndarray:
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate([[x[0] - (mid[0] - x[0])], mid, [x[-1] + (x[-1] - mid[-1])]])


def _chains(surface: DriftSurface, stable: bool, tol: float) -> list[list[SurfaceZero]]:
    """Zeros of one kind linked across neighbouring betas (nearest within `tol`)."""
    betas = sorted(surface.betas)
    left = {b: [z for z in surface.zeros_at(b) if z.stable == stable] for b in betas}
    chains: list[list[SurfaceZero]] = []
    for k, b in enumerate(betas):
        while left[b]:
            chain = [left[b].pop(0)]
            for b2 in betas[k + 1 :]:
                near = [z for z in left[b2] if abs(z.d31 - chain[-1].d31) <= tol]
                if not near:
                    break
                nxt = min(near, key=lambda z: abs(z.d31 - chain[-1].d31))
                left[b2].remove(nxt)
                chain.append(nxt)
            chains.append(chain)
    return chains


def fig8_surface(
    surface: DriftSurface,
    path: Path,
    paper: PaperValues,
    sweeps: dict[str, Any] | None = None,
    cells: Sequence[AtlasPoint] = (),
) -> None:
    """The heat map, zeros, branches, folds, (if given) Fig. 6a's sweeps and the stable
    states only settled walks found (`cells`, issue 52: the table's ranges count them)."""
    betas, ds, z = _grid(surface)
    fig, ax = plt.subplots(figsize=(9.0, 5.6))
    lim = float(np.nanmax(np.abs(z))) if np.isfinite(z).any() else 1.0
    norm = SymLogNorm(linthresh=1.0, vmin=-lim, vmax=lim, base=10)
    mesh = ax.pcolormesh(_edges(betas), _edges(ds), z, cmap="RdBu_r", norm=norm, shading="flat")
    fig.colorbar(mesh, ax=ax, label="drift of Δ31 per gait cycle (mrad; red: Δ31 grows)")
    tol = surface.config.link_tol_rad
    for stable, style in ((True, "-"), (False, "--")):
        for chain in _chains(surface, stable, tol):
            xs, ys = [c.beta for c in chain], [c.d31 for c in chain]
            ax.plot(xs, ys, style, color="k", lw=1.4 if stable else 1.0)
            for c in chain:
                ax.plot(
                    c.beta,
                    c.d31,
                    "o",
                    ms=4 if c.resolved else 3,
                    mec="k",
                    mfc="k" if stable else "white",
                    alpha=1.0 if c.resolved else 0.5,
                )
    for n in surface.near_zeros:
        ax.plot([n.beta, n.beta], [n.lo, n.hi], color="0.4", lw=3, alpha=0.5, solid_capstyle="butt")
    for f in surface.folds:
        x = 0.5 * (f.beta_lo + f.beta_hi)
        ax.errorbar(
            x,
            f.d31,
            xerr=0.5 * f.resolution,
            fmt="x",
            color="gold",
            mec="k",
            ms=8,
            capsize=3,
            lw=1.2,
        )
    walked = [(c.beta, x) for c in cells for x in walked_states(c)]
    if walked:
        wb, wx = zip(*walked, strict=True)
        ax.plot(wb, wx, "D", ms=5, mec="k", mfc="gold", label="settled walk (surface unresolved)")
    if sweeps:
        for key, colour, label in (
            ("sweep_series", "tab:purple", "Fig. 6a sweep 0.70 → 0.62"),
            ("sweep_up_series", "tab:orange", "Fig. 6a sweep 0.62 → 0.70"),
        ):
            s = sweeps.get(key)
            if s:
                ax.plot(s["value"], s["d31"], ".", ms=1.5, color=colour, alpha=0.6, label=label)
    top = float(ds[-1])
    for a, b, name, y in (
        (*paper.tripod_stable, "paper: tripod stable", top - 0.02),
        (*paper.metachronal_stable, "paper: metachronal stable", top - 0.14),
    ):
        ax.plot([a, b], [y, y], color="0.2", lw=4, alpha=0.7, solid_capstyle="butt")
        ax.text(b + 0.002, y, name, va="center", fontsize=7)
    ax.set_xlim(betas[0] - 0.005, betas[-1] + 0.005)
    ax.set_ylim(ds[0] - 0.05, ds[-1] + 0.05)
    ax.set_xlabel("duty factor β")
    ax.set_ylabel("held Δ31 (grid) / sampled Δ31 (zeros), rad")
    ax.set_title(
        "Fig. 8 from the drift surface: zeros are gaits (● stable, ○ unstable; faint: "
        "unresolved),\ngrey bars: |drift| inside the noise floor, × folds (± the grid's β step)",
        fontsize=9,
    )
    if sweeps or walked:
        ax.legend(loc="center right", fontsize=7, markerscale=2)
    _save(fig, path)


# --- Fig. 7 -------------------------------------------------------------------------------------
def fig7_surface(
    surface: DriftSurface, path: Path, betas: Sequence[float], free: dict[float, Any]
) -> None:
    """Return maps from the surface, with the settled free-run pairs (`free[beta]`:
    {'x': [...], 'y': [...]}) as dots; below, the same as distances from the diagonal."""
    fig, axes = plt.subplots(
        2,
        len(betas),
        figsize=(4.2 * len(betas), 7.0),
        squeeze=False,
        gridspec_kw={"height_ratios": [3, 2]},
    )
    for k, beta in enumerate(betas):
        pts = surface.curve_at(beta)
        x = np.array([float(p.d31 or 0.0) for p in pts])
        d = np.array([float(p.drift or 0.0) for p in pts])
        top, bottom = axes[0][k], axes[1][k]
        f = free.get(beta) or {}
        fx, fy = np.asarray(f.get("x", []), float), np.asarray(f.get("y", []), float)
        top.plot(fx, fy, ".", ms=1.5, color="0.6", label="free runs (settled)")
        top.plot(x, x + 4 * d, "-", color="tab:blue", lw=1.2, label="surface: Δ31 + 4 d(Δ31)")
        top.plot([1.3, 3.5], [1.3, 3.5], color="k", lw=0.6)
        bottom.plot(fx, MRAD * (fy - fx), ".", ms=1.5, color="0.6")
        bottom.plot(x, MRAD * 4 * d, "-", color="tab:blue", lw=1.2)
        bottom.axhline(0.0, color="k", lw=0.6)
        for z in surface.zeros_at(beta):
            style = {"mfc": "tab:blue" if z.stable else "white", "mec": "tab:blue", "ms": 6}
            top.plot(z.d31, z.d31, "o", **style)
            bottom.plot(z.d31, 0.0, "o", **style)
        for n in (n for n in surface.near_zeros if abs(n.beta - beta) < 1e-9):
            bottom.axvspan(n.lo, n.hi, color="0.85")
        top.set_xlim(1.3, 3.5)
        top.set_ylim(1.3, 3.5)
        top.set_title(f"β = {beta:g}: " + (pattern(window_zeros(surface, beta)) or "no zero"))
        top.set_xlabel("Δ31[n] (rad)")
        bottom.set_xlim(1.3, 3.5)
        bottom.set_ylim(-30, 30)
        bottom.set_xlabel("Δ31[n] (rad)")
        if k == 0:
            top.set_ylabel("Δ31[n+4] (rad)")
            bottom.set_ylabel("Δ31[n+4] − Δ31[n] (mrad)")
            top.legend(fontsize=7, loc="upper left", markerscale=4)
    fig.suptitle(
        "Fig. 7 from the drift surface (● stable, ○ unstable; grey bands: |d| inside "
        "the noise floor), free runs as dots",
        fontsize=9,
    )
    _save(fig, path)


# --- the mechanism ------------------------------------------------------------------------------
def mechanism(surfaces: dict[str, DriftSurface], betas: Sequence[float], path: Path) -> None:
    """Mean jumps e1 (fore), e3 (middle), e5 (hind) against sampled Delta31, a column per beta
    and a row per ground, with the timing lines L_DW and L_FH."""
    grounds = list(surfaces)
    fig, axes = plt.subplots(
        len(grounds),
        len(betas),
        figsize=(4.2 * len(betas), 3.2 * len(grounds)),
        squeeze=False,
        sharey=True,
    )
    legs = ((0, "e1 fore", "tab:red"), (2, "e3 middle", "tab:blue"), (4, "e5 hind", "tab:green"))
    for r, ground in enumerate(grounds):
        s = surfaces[ground]
        for k, beta in enumerate(betas):
            ax = axes[r][k]
            pts = s.curve_at(beta)
            x = [float(p.d31 or 0.0) for p in pts]
            for leg, name, colour in legs:
                y = [
                    math.nan if p.jumps[leg] is None else MRAD * float(p.jumps[leg] or 0.0)
                    for p in pts
                ]
                ax.plot(x, y, ".-", ms=3, lw=1, color=colour, label=name)
            d = [MRAD * float(p.drift or 0.0) for p in pts]
            ax.plot(x, d, "-", color="k", lw=1.4, label="drift per cycle")
            ax.axhline(0.0, color="0.5", lw=0.6)
            ax.axvline(2 * math.pi * (1 - beta), color="0.3", ls="--", lw=0.9)
            ax.axvline(math.pi * beta, color="0.3", ls=":", lw=0.9)
            ax.set_title(f"{ground} ground, β = {beta:g}\n-- L_DW 2π(1−β), ·· L_FH πβ", fontsize=8)
            ax.set_xlim(1.3, 3.5)
            ax.set_ylim(-120, 60)
            ax.set_xlabel("Δ31 sampled (rad)")
            if k == 0:
                ax.set_ylabel("mean jump (mrad; > 0: lands early)")
    axes[0][0].legend(fontsize=7, loc="lower left")
    _save(fig, path)


def _save(fig: Any, path: Path) -> None:
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)

"""Figs. 7 and 8 of `reproduce`, read from the drift surface (`paper.surface`), with the checks
that come with it on every run.

- The surface over `ReproduceConfig.surface_betas` on today's ground gives Fig. 8 (the heat map, its
  zeros, branches and folds, Fig. 6a's sweeps on top) and Fig. 7 (the return maps at the map
  betas). Fig. 7 is checked on its own axes against independent free runs: the finder's spread
  starts at each map beta (`figures.fig7_tasks`), whose settled ends must lie on the surface's
  stable zeros (`free_runs_on_zeros`).
- The protocol's own checks on a sample (`surface_check.SAMPLE_BETAS` x `SAMPLE_D31`): the pin
  at a third of its gain (K/3) and the physics step halved (dt/2), beside the same probes of the
  surface.
- The mechanism: the same surface on the paper's ground at `MECHANISM_BETAS`, for the per-leg
  jumps drawn beside today's ground.

The fixed-point finder (`finder`) is no longer part of reproduce: it is the
independent check (`insect-gait surface-check`, `finder-check`).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from sim_core.contract.results import SURFACE_FILE
from sim_core.contract.surface import AtlasPoint, AtlasWalk, DriftSurface, SurfaceConfig, WalkConfig
from sim_core.contract.template import RunTemplate
from sim_core.contract.values import PaperValues
from sim_core.model.gait import angle_diff, classify_gait, settling
from sim_core.model.params import ModelParams
from sim_core.paper.analysis import PAPER_WINDOW
from sim_core.paper.figures import FigureData, Lookup, ReproduceConfig, figure_tasks
from sim_core.paper.returnmap import return_map_from_series
from sim_core.paper.surface import drift_surface
from sim_core.paper.surface_atlas import atlas_points
from sim_core.paper.surface_check import SAMPLE_BETAS, SAMPLE_D31, VariantRow, variant_rows
from sim_core.paper.surface_figures import decided_ranges, fig7_rows, fig8_rows
from sim_core.paper.surface_walks import read_walk, walk_cells, walk_spec
from sim_core.runs.backends import Backend, Executor, RunStats, run_tasks
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import execute_chunk, run_task

MECHANISM_BETAS = (0.62, 0.655, 0.70)  # the mechanism figure's columns
# A ghost on the surface: where |d| dips, without changing sign, to at most this share of its
# largest value on either side: a free run slows there at least twofold (the finder's ghost is
# the slowest passage of a free run: the same bottleneck, read without running through it)
GHOST_DIP = 0.5
# a settled free run lies on the surface when a stable zero (or a near-zero band) is this close:
# the matching tolerance for stable states
FREE_RUN_TOL = 0.03


@dataclass
class SurfaceStudy:
    """The surfaces behind Figs. 7-8 and what was spent on them."""

    surface: DriftSurface  # today's ground, Fig. 8's betas
    paper_ground: DriftSurface  # the paper's ground at MECHANISM_BETAS
    checks: list[VariantRow] = field(default_factory=list)  # K/3 and dt/2 on the sample
    checks_ok: bool = False
    stats: RunStats = field(default_factory=RunStats)
    surface_wall_s: float = 0.0  # the main surface alone
    wall_s: float = 0.0  # everything
    # the surface's cells decided by settled free walks where it cannot tell (issue 52,
    # point 1; `surface_walks.walk_cells`, as the atlas decides its cells); empty: not walked
    cells: list[AtlasPoint] = field(default_factory=list)
    # the decided ranges against settled walks at betas off the grid (`off_grid_checks`)
    off_grid: list[OffGrid] = field(default_factory=list)


@dataclass(frozen=True)
class OffGrid:
    """A settled walk at a beta between the surface's grid betas, beside a Fig. 8 range end:
    whether it holds `gait` (settles on a state of it) as the range says it should."""

    gait: str
    beta: float
    expected: bool  # inside the decided range: the gait should hold here
    walk: AtlasWalk

    @property
    def holds(self) -> bool | None:
        """Whether the walk settled on a state of `gait`; one that has not settled has left
        the gait if its last quarter lies off it (it started on it), else it is undecided
        (None), as is a failed walk."""
        w = self.walk
        if w.final is None:
            return None
        on = classify_gait(w.final, self.beta) == self.gait
        if not w.settled:
            return False if not on else None
        return on

    @property
    def agrees(self) -> bool:
        return self.holds is self.expected


def surface_study(
    betas: Sequence[float],
    cfg: SurfaceConfig,
    params: ModelParams,
    cache: ResultCache,
    backend: Backend,
    *,
    progress: bool = True,
    executor: Executor = execute_chunk,
    mechanism_refine: bool = True,
    walks: WalkConfig | None = None,
    last_pass_betas: Sequence[float] | None = None,
) -> SurfaceStudy:
    """The surface over `betas` on `params`' ground, the mechanism's surface on the paper's
    ground (refined as `drift_surface` does only with `mechanism_refine`) and the K/3 and dt/2
    sample, all through `cache` and `backend`. With `walks`, the surface's cells are decided by
    settled free walks where it cannot tell, and the decided ranges' ends are checked by walks
    off the grid (`off_grid_checks`)."""
    t0 = time.perf_counter()
    stats = RunStats()
    kw: dict[str, Any] = {"cache": cache, "backend": backend, "progress": progress,
                          "stats": stats, "executor": executor}  # fmt: skip
    surface = drift_surface(betas, config=cfg, params=params, last_pass_betas=last_pass_betas,
                            **kw)  # fmt: skip
    t_surface = time.perf_counter() - t0
    penalty = params.replace(**{"ground": "penalty"})
    paper_ground = drift_surface(MECHANISM_BETAS, config=cfg, params=penalty,
                                 refine=mechanism_refine, **kw)  # fmt: skip
    sample = replace(cfg, d31_grid=SAMPLE_D31)
    variants = {
        "K/3": drift_surface(
            SAMPLE_BETAS, config=replace(sample, gain_per_s=cfg.gain_per_s / 3), params=params,
            refine=False, **kw,
        ),
        "dt/2": drift_surface(
            SAMPLE_BETAS, config=sample, params=params, refine=False,
            template=RunTemplate.model_validate({"dt_s": params.numerics.dt / 2}), **kw,
        ),
    }  # fmt: skip
    checks, ok = variant_rows(surface, variants, cfg.floor_rad)
    cells: list[AtlasPoint] = []
    off: list[OffGrid] = []
    if walks is not None:
        base = RunTemplate()  # the surface's cells: the default body, level
        mass_g = base.spec().body_mass_g
        cells = walk_cells([(pt, surface, base) for pt in atlas_points(surface, mass_g)],
                           cache=cache, backend=backend, params=params, config=walks,
                           chunk_size=cfg.chunk_size, progress="walks" if progress else False,
                           stats=stats, executor=executor)  # fmt: skip
        off = off_grid_checks(cells, params, cache, backend, walks, stats=stats,
                              executor=executor)  # fmt: skip
    return SurfaceStudy(surface, paper_ground, checks, ok, stats, t_surface,
                        time.perf_counter() - t0, cells, off)  # fmt: skip


def off_grid_betas(cells: Sequence[AtlasPoint], gait: str) -> list[tuple[float, bool, float]]:
    """(beta, expected, start) beside each end of `gait`'s decided ranges inside the grid:
    midway to the grid beta inside the range (the gait should hold there: the range says both
    neighbours hold it) and midway between the next two outside it (it should not), each
    walked from the end cell's state of `gait` nearest the paper's branch."""
    cs = sorted(cells, key=lambda c: c.beta)
    bs = [c.beta for c in cs]
    out: list[tuple[float, bool, float]] = []
    for lo, hi in decided_ranges(cs, gait):
        for end, inward in ((hi, -1), (lo, +1)):
            k = bs.index(end)
            if k in (0, len(bs) - 1):  # the grid's edge, not the range's end
                continue
            states = [x for x, g in zip(cs[k].stable, cs[k].gaits, strict=True) if g == gait]
            if not states:
                continue
            start = min(states, key=lambda x: abs(x - (2.9 if gait == "tripod" else 1.9)))
            j = k + inward  # inside the range
            if 0 <= j < len(bs) and (lo <= bs[j] <= hi):
                out.append((round(0.5 * (bs[k] + bs[j]), 6), True, start))
            a, b = k - inward, k - 2 * inward  # the next two outside it
            if 0 <= a < len(bs) and 0 <= b < len(bs):
                out.append((round(0.5 * (bs[a] + bs[b]), 6), False, start))
    return out


def off_grid_checks(
    cells: Sequence[AtlasPoint],
    params: ModelParams,
    cache: ResultCache,
    backend: Backend,
    walks: WalkConfig,
    *,
    stats: RunStats | None = None,
    executor: Executor = execute_chunk,
) -> list[OffGrid]:
    """Settled walks at betas off the grid beside every end of the decided tripod and
    metachronal ranges (`off_grid_betas`): does each hold its gait where the range says?"""
    plan = [(g, b, e, x) for g in ("tripod", "metachronal") for b, e, x in off_grid_betas(cells, g)]
    tasks = [run_task(walk_spec(b, x, walks, RunTemplate()), params) for _, b, _, x in plan]
    results, st = run_tasks(tasks, cache, backend, 1, False, executor)
    if stats is not None:
        for name in ("tasks", "computed", "cached", "compute_s"):
            setattr(stats, name, getattr(stats, name) + getattr(st, name))
    return [OffGrid(g, b, e, read_walk(x, results[t.key], walks.duration_s))
            for (g, b, e, x), t in zip(plan, tasks, strict=True)]  # fmt: skip


# --- what Fig. 7 reads --------------------------------------------------------------------------
def ghosts(surface: DriftSurface, beta: float, floor_rad: float) -> list[tuple[float, float]]:
    """(Delta31, drift) of each ghost at `beta` inside the paper's window: the deepest point of
    a dip of |d| between two zeros (or a zero and the window's edge), where |d| falls to at
    most GHOST_DIP of its largest value on either side, the drift keeping its sign (beyond
    `floor_rad`) throughout: a bottleneck free runs crawl through."""
    lo, hi = PAPER_WINDOW
    pts = [p for p in surface.curve_at(beta) if lo <= float(p.d31 or 0.0) <= hi]
    x = np.array([float(p.d31 or 0.0) for p in pts])
    d = np.array([float(p.drift or 0.0) for p in pts])
    # split where floor-clearing probes change sign: each segment keeps one sign
    segments: list[list[int]] = [[]]
    sign = 0.0
    for k, v in enumerate(d):
        if abs(v) > floor_rad:
            if sign and np.sign(v) != sign:
                segments.append([])
            sign = float(np.sign(v))
        segments[-1].append(k)
    out: list[tuple[float, float]] = []
    for seg in segments:
        a = np.abs(d[seg])
        for j in range(1, len(seg) - 1):
            if a[j] > a[j - 1] or a[j] > a[j + 1]:
                continue
            if a[j] <= GHOST_DIP * min(a[:j].max(), a[j + 1 :].max()):
                out.append((float(x[seg[j]]), float(d[seg[j]])))
    return out


def free_runs(results: Sequence[dict[str, Any]], beta: float) -> dict[str, Any]:
    """The free runs at one map beta: settled finals, and the return-map pairs of the settled
    and of the unsettled runs (`return_map_from_series`)."""
    settled: list[list[float]] = []
    unsettled: list[list[float]] = []
    finals: list[float] = []
    for r in results:
        if r.get("error") is not None:
            continue
        st = settling(r["d31"])
        (settled if st.settled else unsettled).append(r["d31"])
        if st.settled and st.final is not None:
            finals.append(float(st.final))
    rm, un = return_map_from_series(beta, settled), return_map_from_series(beta, unsettled)
    return {"finals": finals, "x": rm.x.tolist(), "y": rm.y.tolist(),
            "x_unsettled": un.x.tolist(), "y_unsettled": un.y.tolist(),
            "unsettled": len(unsettled)}  # fmt: skip


def free_runs_on_zeros(surface: DriftSurface, beta: float, finals: Sequence[float]) -> list[float]:
    """The settled finals inside the held range (`config.d31_grid`) with no stable zero of the
    surface within FREE_RUN_TOL (nor inside a near-zero band, where the surface cannot tell):
    what the figure would contradict. A state off the family the pin holds (Delta53 =
    Delta31, the right side as the left) lands here too: the surface cannot see it."""
    stable = [z.d31 for z in surface.zeros_at(beta) if z.stable]
    bands = [(n.lo, n.hi) for n in surface.near_zeros if abs(n.beta - beta) < 1e-9]
    return [
        f
        for f in held(surface, finals)  # idempotent: callers may pass held values
        if not any(abs(float(angle_diff(f, s))) <= FREE_RUN_TOL for s in stable)
        and not any(lo - FREE_RUN_TOL <= f <= hi + FREE_RUN_TOL for lo, hi in bands)
    ]


def held(surface: DriftSurface, xs: Sequence[float]) -> list[float]:
    """The values of `xs` inside the surface's held range of Delta31 (rad)."""
    grid = surface.config.d31_grid or (0.0, 2 * np.pi)
    return [x for x in xs if min(grid) <= x <= max(grid)]


def _fig7(
    study: SurfaceStudy, map_betas: Sequence[float], free: dict[float, dict[str, Any]],
    paper: PaperValues,
) -> FigureData:  # fmt: skip
    """Fig. 7: per map beta the surface's curve, zeros, ghosts and the free runs; the summary
    carries the reproduction rows' inputs (`fig7_rows` and, per beta, ghosts and the settled
    free runs that no stable zero explains)."""
    s = study.surface
    floor = s.config.floor_rad
    maps: list[dict[str, Any]] = []
    rows: list[list[Any]] = []
    summary: dict[str, Any] = {"pattern_rows": fig7_rows(s, paper, study.cells or None)}
    for beta in map_betas:
        f = free[beta]
        zeros = [z.model_dump() for z in s.zeros_at(beta)]
        gh = ghosts(s, beta, floor)
        inside = held(s, f["finals"])
        off = free_runs_on_zeros(s, beta, inside)
        pts = sorted(s.points_at(beta), key=lambda p: float(p.d31 or p.pin_d31))
        rows += [[beta, p.pin_d31, p.d31, p.drift, int(p.usable)] for p in pts]
        maps.append({"beta": beta, "zeros": zeros, "ghosts": gh, "free": f, "off_zeros": off})
        summary[str(beta)] = {
            "ghosts": [g[0] for g in gh],
            "finals": f["finals"],
            "outside": [x for x in f["finals"] if x not in inside],
            "off_zeros": off,
            "unsettled": f["unsettled"],
        }
    data = {"maps": maps, "lag": 4, "window_rad": PAPER_WINDOW}
    header = ["beta", "pin_d31_rad", "d31_rad", "drift_rad_per_cycle", "usable"]
    return FigureData("fig7", data, {"fig7": (header, rows)}, summary)


def _fig8(
    study: SurfaceStudy, sweeps: dict[str, Any], paper: PaperValues, beta_tol: float
) -> FigureData:
    """Fig. 8: the whole surface, Fig. 6a's two sweeps, the study's cost and checks; the
    summary carries `fig8_rows` and the sample checks' largest differences."""
    s = study.surface
    rows = [[z.beta, z.d31, int(z.stable), int(z.resolved), z.slope] for z in s.zeros]
    worst: dict[str, float | None] = {}
    for r in study.checks:  # None where a probe is missing on either side
        prev = worst.get(r.variant, 0.0)
        worst[r.variant] = None if r.diff is None or prev is None else max(prev, abs(r.diff))
    data = {
        "surface_file": SURFACE_FILE,  # the surface itself, written once beside this file
        "cells": [c.model_dump() for c in study.cells],  # decided by walks (issue 52)
        "checks": [asdict(r) | {"diff": r.diff} for r in study.checks],
        "checks_ok": study.checks_ok,
        **sweeps,
    }
    summary = {
        "range_rows": fig8_rows(s, paper, beta_tol, study.cells or None),
        "off_grid": [
            {
                "gait": o.gait,
                "beta": o.beta,
                "expected": o.expected,
                "holds": o.holds,
                "final": o.walk.final,
                "start": o.walk.start,
            }
            for o in study.off_grid
        ],
        "checks_ok": study.checks_ok,
        "checks_worst": worst,
        "floor_rad": s.config.floor_rad,
        "probes": len(s.points),
        "sim_s": s.sim_s,
        "surface_wall_s": study.surface_wall_s,
    }
    header = ["beta", "d31_rad", "stable", "resolved", "slope"]
    return FigureData("fig8", data, {"fig8": (header, rows)}, summary)


def surface_figure_data(
    study: SurfaceStudy,
    figs: Sequence[str],
    cfg: ReproduceConfig,
    p: ModelParams,
    get: Lookup,
    out: Path,
    paper: PaperValues,
    beta_tol: float,
) -> list[FigureData]:
    """The asked-for Figs. 7 and 8 from `study` (and the free runs and sweeps of
    `figure_tasks`, read with `get`), drawn into `out` (fig7.png, fig8.png, mechanism.png)."""
    free: dict[float, dict[str, Any]] = {}
    if "7" in figs:  # Fig. 7's free runs are run only when Fig. 7 is asked for
        tasks = figure_tasks("7", cfg, p)
        free = {b: free_runs([get(t) for t in tasks if t.run_spec().beta == b], b)
                for b in cfg.map_betas}  # fmt: skip
    sweeps: dict[str, Any] = {}
    if "8" in figs:
        down, up = (get(t) for t in figure_tasks("8", cfg, p))
        sweeps = {"sweep_series": {k: down[k] for k in ("value", "d31")},
                  "sweep_up_series": {k: up[k] for k in ("value", "d31")}}  # fmt: skip
    out.mkdir(parents=True, exist_ok=True)
    draw(study, out, paper, cfg.map_betas, free if "7" in figs else None, sweeps)
    fds = []
    if "7" in figs:
        fds.append(_fig7(study, cfg.map_betas, free, paper))
    if "8" in figs:
        fds.append(_fig8(study, sweeps, paper, beta_tol))
    return fds


def draw(
    study: SurfaceStudy,
    out: Path,
    paper: PaperValues,
    map_betas: Sequence[float],
    free: dict[float, Any] | None,
    sweeps: dict[str, Any] | None,
) -> list[Path]:
    """fig7.png (unless `free` is None: Fig. 7 not asked for), fig8.png and (with the paper's
    ground) mechanism.png into `out`."""
    from sim_core.paper.surface_figures import fig7_surface, fig8_surface, mechanism

    files = [out / "fig8.png", out / "mechanism.png"]
    if free is not None:
        files.insert(0, out / "fig7.png")
        fig7_surface(study.surface, files[0], map_betas, free)
    fig8_surface(study.surface, files[-2], paper, sweeps, study.cells)
    surfaces = {study.surface.ground: study.surface, "penalty": study.paper_ground}
    mechanism(surfaces, MECHANISM_BETAS, files[-1])
    return files

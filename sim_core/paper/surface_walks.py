"""Deciding an atlas cell by walking where its drift surface cannot.

Why. The surface reads a gait as a zero of the drift at held Delta31; where |d| stays inside
the pin's own bias (0.1-0.3 mrad per cycle) it can only say "a zero may be here" (an
unresolved zero, a near-zero band). The tripod at beta 0.62-0.64 is such a narrow pair (the
drift touches zero between 2.88 and 2.98): an atlas without the surface's finer last pass
called beta 0.62, 3 g "metachronal only" while a walk from 3.0 holds the tripod at 2.953.
Free walks decide it: a stable state there is where a walk from beside it settles.

How. A cell is walked only where the answer could change its region (`region`): a span (an
unresolved zero's bracket or a near-zero band in `PAPER_WINDOW`) whose Delta31 could hold a
gait that would change the region. Such a cell walks from just outside each open span on both
sides (`WalkConfig.margin_rad`) and from near the paper's two branches (`PAPER_STARTS`), as
`sim_core.runs` tasks (cached, on the atlas's backend), read by the one settled rule
(`gait.settling`). Every settled final in the window is a stable state of the cell (provenance
"walk", or "surface+walk" where the surface has a stable zero within `CLUSTER_TOL`); a walk
that did not settle leaves the cell unresolved (`AtlasPoint.undecided`), never guessed.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim_core.contract.finder import CLUSTER_TOL
from sim_core.contract.surface import (
    AtlasPoint,
    AtlasWalk,
    DriftSurface,
    SurfaceZero,
    WalkConfig,
    region,
)
from sim_core.contract.template import RunTemplate
from sim_core.model.gait import classify_gait, settling
from sim_core.model.params import ModelParams
from sim_core.model.spec import RunSpec
from sim_core.paper.analysis import PAPER_WINDOW
from sim_core.paper.finder_runs import cluster_finals
from sim_core.runs.backends import Backend, Executor, RunStats, run_tasks
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import execute_chunk, run_task

# How finely a span's Delta31 is scanned for the gaits it could hold (`classify_gait`'s
# borders move by ~0.02 rad per 0.01 of beta; 0.01 rad cannot step over a gait).
SCAN_STEP_RAD = 0.01


def window_zeros(surface: DriftSurface, beta: float) -> list[SurfaceZero]:
    """The surface's zeros at `beta` inside `PAPER_WINDOW` (the atlas's question)."""
    lo, hi = PAPER_WINDOW
    return [z for z in surface.zeros_at(beta) if lo <= z.d31 <= hi]


def spans_at(surface: DriftSurface, beta: float) -> list[tuple[float, float]]:
    """The (lo, hi) of every unresolved zero and near-zero band at `beta` that reaches into
    `PAPER_WINDOW`: where the surface may hide a zero it could not resolve."""
    lo, hi = PAPER_WINDOW
    spans = [(z.lo, z.hi) for z in surface.zeros_at(beta) if not z.resolved]
    spans += [(n.lo, n.hi) for n in surface.near_zeros if abs(n.beta - beta) < 1e-9]
    return sorted((a, b) for a, b in spans if b >= lo and a <= hi)


def could_hold(span: tuple[float, float], beta: float) -> set[str]:
    """The gaits (`classify_gait`) a state inside `span` could have at `beta`."""
    a, b = span
    xs = np.append(np.arange(a, b, SCAN_STEP_RAD), b)
    return {classify_gait(float(x), beta) for x in xs}


def certain_gaits(surface: DriftSurface, beta: float) -> list[str]:
    """The gaits the surface's stable zeros at `beta` name for sure: a resolved zero's, or an
    unresolved one's whose whole bracket is of one gait (else its place, and so its gait, is
    a guess: the bracket's middle or the raw drift's crossing)."""
    out = []
    for z in window_zeros(surface, beta):
        if z.stable:
            held = {classify_gait(z.d31, beta)} if z.resolved else could_hold((z.lo, z.hi), beta)
            out += list(held) if len(held) == 1 else []
    return out


def open_spans(
    beta: float, gaits: Sequence[str], spans: Sequence[tuple[float, float]]
) -> list[tuple[float, float]]:
    """The spans where a hidden stable state would change the region the certain `gaits`
    make: those that could hold a gait g with region(gaits + [g]) != region(gaits)."""
    now = region(gaits)
    return [s for s in spans if any(region([*gaits, g]) != now for g in could_hold(s, beta))]


def walk_starts(spans: Sequence[tuple[float, float]], cfg: WalkConfig) -> list[float]:
    """Starts on both sides of each span and near the paper's branches (none if no span),
    sorted, those within `cfg.merge_rad` of an earlier one dropped."""
    if not spans:
        return []
    raw = [x for a, b in spans for x in (a - cfg.margin_rad, b + cfg.margin_rad)]
    out: list[float] = []
    for x in sorted([*raw, *cfg.paper_starts]):
        if not out or x - out[-1] > cfg.merge_rad:
            out.append(round(x, 6))
    return out


def walk_spec(beta: float, start: float, cfg: WalkConfig, template: RunTemplate) -> RunSpec:
    """A free walk (no pin) from Delta31 = `start`: a `cfg.try_s` try, on to `cfg.duration_s`
    only if it has not settled by then; `template` is the cell's run (its surface's template:
    mass, slope, numerics and the rest)."""
    return template.spec(beta=beta, d31_init=start, duration_s=cfg.duration_s,
                         stop_if_settled_s=cfg.try_s)  # fmt: skip


def read_walk(start: float, result: Mapping[str, Any], asked_s: float) -> AtlasWalk:
    """A walk's outcome by the core's settled rule (`gait.settling` of its Delta31 series)."""
    error = result.get("error")
    length = float(result.get("duration_s") or asked_s)
    if error:
        return AtlasWalk(start=start, final=None, settled=False, why=str(error), sim_s=length)
    s = settling(list(result.get("d31") or []))
    return AtlasWalk(start=start, final=s.final, settled=s.settled, why=s.why, sim_s=length)


@dataclass
class _State:
    """A stable state of a cell while it is decided: where, from what, and (for an unresolved
    zero of the surface) the bracket it lies in."""

    d31: float
    source: str
    bracket: tuple[float, float] | None = None

    def holds(self, final: float) -> bool:
        """Whether a walk settling at `final` reached this state."""
        inside = self.bracket is not None and self.bracket[0] <= final <= self.bracket[1]
        return inside or abs(self.d31 - final) <= CLUSTER_TOL


def decide(
    point: AtlasPoint,
    walks: Sequence[AtlasWalk],
    brackets: Sequence[tuple[float, float] | None] = (),
) -> AtlasPoint:
    """The cell with its walks: the surface's stable zeros and every settled walk's final in
    the window (finals within CLUSTER_TOL are one), each with its provenance; gaits and
    region from that union. A final inside an unresolved stable zero's bracket (`brackets`,
    parallel to `point.stable`, None where resolved) or within CLUSTER_TOL of a zero is that
    zero, placed where the walk settled if the surface could not place it. An unsettled walk
    is kept, and makes the cell `undecided`."""
    lo, hi = PAPER_WINDOW
    spans = list(brackets) or [None] * len(point.stable)
    states = [_State(x, "surface", b) for x, b in zip(point.stable, spans, strict=True)]
    finals = [w.final for w in walks if w.settled and w.final is not None and lo <= w.final <= hi]
    for f, _ in cluster_finals(finals):
        same = next((st for st in states if st.holds(f)), None)
        if same is None:
            states.append(_State(f, "walk"))
            continue
        same.source = "surface+walk"
        if same.bracket is not None:  # placed now: a second final in the bracket is another
            same.d31, same.bracket = f, None
    states.sort(key=lambda st: st.d31)
    gaits = [classify_gait(st.d31, point.beta) for st in states]
    return point.model_copy(
        update={
            "stable": [st.d31 for st in states],
            "gaits": gaits,
            "region": region(gaits),
            "provenance": [st.source for st in states],
            "walks": list(walks),
            "checked": True,
        }
    )


def stable_brackets(surface: DriftSurface, beta: float) -> list[tuple[float, float] | None]:
    """Per stable zero of the window at `beta`: its bracket if unresolved, else None (what
    `decide` places a walk's final in)."""
    zs = [z for z in window_zeros(surface, beta) if z.stable]
    return [None if z.resolved else (z.lo, z.hi) for z in zs]


def walk_cells(
    cells: Sequence[tuple[AtlasPoint, DriftSurface, RunTemplate]],
    *,
    cache: ResultCache,
    backend: Backend,
    params: ModelParams,
    config: WalkConfig | None = None,
    chunk_size: int = 8,
    progress: bool | str = True,
    stats: RunStats | None = None,
    on_progress: Callable[[float], None] | None = None,
    executor: Executor = execute_chunk,
    n_betas: int | None = None,
) -> list[AtlasPoint]:
    """Each (cell, its surface, its run template) decided: the
    walks of every cell that has an open span go to the backend as one batch; a cell with none
    comes back checked, unchanged (`on_progress` hears that batch). With `n_betas` (the cells
    are a value-major grid of that many betas), each cell is then also walked from the paper's
    start of every gait a neighbour holds and it lacks, round after round (`neighbour_rounds`).
    """
    cfg = config or WalkConfig()
    brackets = [stable_brackets(surface, pt.beta) for pt, surface, _ in cells]

    def walked(todo: Sequence[tuple[int, float]], hear: Callable[[float], None] | None = None
               ) -> dict[int, list[AtlasWalk]]:  # fmt: skip
        """The walks from (cell index, start), read, by cell; through the cache, in one batch."""
        plan = [(k, x, run_task(walk_spec(cells[k][0].beta, x, cfg, cells[k][2]), params))
                for k, x in todo]  # fmt: skip
        tasks = [t for _, _, t in plan]
        results, st = run_tasks(tasks, cache, backend, chunk_size, progress, executor, hear)
        if stats is not None:
            stats.add(st)
        out: dict[int, list[AtlasWalk]] = {k: [] for k in range(len(cells))}
        for k, x, t in plan:
            out[k].append(read_walk(x, results[t.key], cfg.duration_s))
        return out

    spans = [open_spans(pt.beta, certain_gaits(s, pt.beta), spans_at(s, pt.beta))
             for pt, s, _ in cells]  # fmt: skip
    first = walked([(k, x) for k, sp in enumerate(spans) for x in walk_starts(sp, cfg)],
                   on_progress)  # fmt: skip
    points = [decide(pt, first[k], brackets[k]) for k, (pt, _, _) in enumerate(cells)]
    if n_betas is None:
        return points
    return neighbour_rounds(points, cells, brackets, n_betas, cfg, walked)


# The four cells beside a cell of an atlas's (value, beta) grid.
NEIGHBOURS = ((0, -1), (0, 1), (-1, 0), (1, 0))


def neighbour_starts(
    points: Sequence[AtlasPoint], n_betas: int, cfg: WalkConfig
) -> list[list[float]]:
    """Per cell of a value-major grid of `n_betas` betas: the paper's start of each gait that a
    neighbouring cell holds and this cell lacks (`cfg.paper_starts`, named by `classify_gait`
    at the cell's beta), unless the cell has walked from within `cfg.merge_rad` of it."""
    n_values = len(points) // n_betas
    out: list[list[float]] = []
    for k, pt in enumerate(points):
        i, j = divmod(k, n_betas)
        near: set[str] = set()
        for di, dj in NEIGHBOURS:
            ii, jj = i + di, j + dj
            if 0 <= ii < n_values and 0 <= jj < n_betas:
                near |= set(points[ii * n_betas + jj].gaits)
        missing = near - set(pt.gaits)
        starts = [x for x in cfg.paper_starts if classify_gait(x, pt.beta) in missing]
        out.append([x for x in starts
                    if all(abs(w.start - x) > cfg.merge_rad for w in pt.walks)])  # fmt: skip
    return out


def marked_if_left(walk: AtlasWalk, point: AtlasPoint) -> AtlasWalk:
    """`walk` with `left_gait` set where it did not settle but has left the gait it started in
    (`classify_gait` at the cell's beta) for one the cell holds: the question it asked, "does
    that gait live here, reached from its paper start?", is answered no, and wherever it
    settles among the gait it is in now, the cell's region stays."""
    if walk.settled or walk.final is None:
        return walk
    now = classify_gait(walk.final, point.beta)
    if now == classify_gait(walk.start, point.beta) or now not in point.gaits:
        return walk
    return walk.model_copy(update={"left_gait": True})


def neighbour_rounds(
    points: list[AtlasPoint],
    cells: Sequence[tuple[AtlasPoint, DriftSurface, RunTemplate]],
    brackets: Sequence[list[tuple[float, float] | None]],
    n_betas: int,
    cfg: WalkConfig,
    walked: Callable[[Sequence[tuple[int, float]]], dict[int, list[AtlasWalk]]],
) -> list[AtlasPoint]:
    """The decided cells (`points`, value-major, beside their surface-only `cells`), each also
    walked (`walked`: cell index and start -> its walks) from the paper's start of every gait a
    neighbour holds and it lacks (`neighbour_starts`), round after round until no cell needs
    another such walk.

    Why. A cell is walked only where its surface leaves a span open; one whose surface reads a
    single gait with nothing open is not. There a narrow pair (the tripod's near 2.95) can be
    missed by the probes: the same slope atlas on two probe lengths read 5 of 91 cells
    differently, each time a walk from a paper's start settling on a state the other surface
    had closed (docs/REPRODUCTION.md). A gait that lives next door is the one worth looking
    for; each round walks at most the two paper starts per cell, so the rounds end."""
    points = list(points)
    while True:
        todo = [(k, x) for k, xs in enumerate(neighbour_starts(points, n_betas, cfg)) for x in xs]
        if not todo:
            return points
        for k, walks in walked(todo).items():
            if walks:
                new = [marked_if_left(w, points[k]) for w in walks]
                points[k] = decide(cells[k][0], [*points[k].walks, *new], brackets[k])

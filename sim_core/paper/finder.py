"""The settled fixed-point finder: which gaits are stable at one condition, and where the
border between their basins runs, read from settled walking.

Why not a smoothed return map (the old Figs. 7-8): near the branches this model's Delta31
drifts by 0-5 mrad per gait cycle, far below what 3 s runs resolve, and a kernel-smoothed
curve through such data finds zeros where the noise crosses zero. Here every answer comes
from whole runs judged by the one settled rule (`sim_core.model.gait.settling`):

- **stable gaits**: runs from starts spread over the circle (and from the states the
  neighbouring betas found); each settled final is a state (finals within CLUSTER_TOL are
  one), with how many starts reach it and how fast it attracts (the slope of the n -> n+4 map
  at it, fitted to the approach of its runs). A state counts as stable only when runs kicked
  to either side of it come back (`Attractor.confirmed`): one settled run can end where the
  drift merely changes speed (2.12 at beta 0.62 attracts from below only) or on a state whose
  basin, seen from Delta31 starts, is a thin sliver (4.54 at 0.62);
- **unstable gaits**: the border between two basins, by bisection of the start between two
  starts that end on attractors of different gaits, to `border_tol_rad`; the two bracketing
  runs dwell at the unstable fixed point before they part, which gives its Delta31, and the
  growth of their separation gives its slope;
- **ghosts**: where a run that slides on spends the most cycles (its slowest passage), with
  the drift there;
- runs that do not settle in the time given are listed as such, never guessed.

The search is a set of coroutines, one per condition (`Cell`; `finder_cell.cell_search`): each
yields the runs it needs next and receives their results, so every round of every condition
goes to the backend as one batch (`find`). Nothing here simulates: the caller's `run` does
(`reproduce` through the result cache and the local or Dask backend). MuJoCo-free, so the REST
`bifurcation` kind runs this very search (`sim_core.find`) in its worker, as the lab does
through the cache. Its protocol and typed output are the contract's (`sim_core.contract.finder`);
what it reads off runs, `finder_runs`'.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

from sim_core.contract.finder import CLUSTER_TOL, Cell, CellResult, FinderConfig, Probe, RunFn
from sim_core.model.gait import angle_diff, wrap
from sim_core.paper.finder_cell import cell_search
from sim_core.paper.returnmap import initial_values

# Rounds of neighbour seeding along the beta grid (each lends the states the last round found,
# then searches the cells that learnt something again): a state then travels at most this many
# grid steps from where the cell's own runs reached it.
MAX_SEED_ROUNDS = 4


def find(cells: Sequence[Cell], cfg: FinderConfig, run: RunFn) -> list[CellResult]:
    """The finder over many conditions: each round, every search's probes in one `run` call
    (one batch for the backend). `run` takes (cell, probe) pairs and returns one result dict
    per pair with the task result's keys (`d31`, `error`); a probe asked twice is run once.

    With `cfg.neighbour_seeds`, each condition then learns from its neighbours along beta
    (`neighbour_seeds`): a state a neighbour found that it lacks is looked for from that state
    and from the starts that reached it there, and the condition is searched again (its old
    runs are read back, not re-run), round by round until none learns anything new."""
    cells = list(cells)
    memo: dict[tuple[int, Probe], dict[str, Any]] = {}

    def batch(asked: list[tuple[int, Probe]]) -> list[dict[str, Any]]:
        new = list(dict.fromkeys(q for q in asked if q not in memo))
        if new:
            memo.update(zip(new, run([(cells[k], p) for k, p in new]), strict=True))
        return [memo[q] for q in asked]

    results = _run_searches(cells, range(len(cells)), cfg, batch, {})
    for _ in range(MAX_SEED_ROUNDS if cfg.neighbour_seeds and len(cells) > 1 else 0):
        new = [neighbour_seeds(cells, results, k, cfg) for k in range(len(cells))]
        todo = [k for k, n in enumerate(new) if n]
        if not todo:
            break
        for k in todo:
            cells[k] = replace(cells[k], seeds=cells[k].seeds + new[k])
        results = _run_searches(cells, todo, cfg, batch, results)
    return results


def _run_searches(
    cells: list[Cell],
    which: Sequence[int],
    cfg: FinderConfig,
    batch: Callable[[list[tuple[int, Probe]]], list[dict[str, Any]]],
    done: dict[int, CellResult] | list[CellResult],
) -> list[CellResult]:
    """The searches of `which` cells, round by round (one batch each); the others as `done`."""
    results = dict(enumerate(done)) if isinstance(done, list) else dict(done)
    searches = {k: cell_search(cells[k], cfg) for k in which}
    pending = {k: next(s) for k, s in searches.items()}
    while pending:
        outs = batch([(k, p) for k, ps in pending.items() for p in ps])
        i = 0
        nxt: dict[int, list[Probe]] = {}
        for k, ps in pending.items():
            mine, i = outs[i : i + len(ps)], i + len(ps)
            try:
                nxt[k] = searches[k].send(mine)
            except StopIteration as stop:
                results[k] = stop.value
        pending = nxt
    return [results[k] for k in range(len(cells))]


def neighbour_seeds(
    cells: Sequence[Cell], found: Sequence[CellResult], k: int, cfg: FinderConfig
) -> tuple[float, ...]:
    """New starts for cell k: each state that its nearest betas below and above (at its mass
    and slope) found and it did not (none of its states within CLUSTER_TOL), as the state's
    own value and the starts that reached it there; none it has run already."""
    c = cells[k]
    same = [j for j, o in enumerate(cells)
            if (o.body_mass_g, o.slope_deg) == (c.body_mass_g, c.slope_deg)]  # fmt: skip
    below = [j for j in same if cells[j].beta < c.beta]
    above = [j for j in same if cells[j].beta > c.beta]
    near = [max(below, key=lambda j: cells[j].beta)] if below else []
    near += [min(above, key=lambda j: cells[j].beta)] if above else []
    mine = [a.d31 for a in found[k].attractors]
    tried = {round(r.d31_init, 9) for r in found[k].runs}
    tried |= {round(float(x), 9) for x in (*initial_values(cfg.starts), *c.seeds)}
    out: list[float] = []
    for j in near:
        for i, a in enumerate(found[j].attractors):
            if any(abs(float(angle_diff(a.d31, m))) <= CLUSTER_TOL for m in mine):
                continue
            reached = [r.d31_init for r in found[j].runs if r.attractor == i]
            for x in (a.d31, *reached):
                x = float(wrap(x))
                if round(x, 9) not in tried and round(x, 9) not in {round(o, 9) for o in out}:
                    out.append(x)
    return tuple(out)

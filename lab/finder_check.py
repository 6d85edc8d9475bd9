"""Is the finder right? Its answers checked against independent long runs.

Two checks at each beta:

- **reached**: every stable point the finder reports is reached by an independent run
  started near it: runs from `NUDGE` rad below and above it (outside the finder's own kicks,
  `FinderConfig.kick_rad`, so no run is shared), at least one of which settles within `MATCH`
  of it (the issue's "an independent 40 s run started near it"); both are reported;
- **complete**: every attractor that `starts` independent runs reach (starts offset by half a
  spacing from the finder's own, so no run is shared) appears in the finder's output within
  `MATCH`, as a stable point or as a state its kicks confirmed from one side only. Runs that
  do not settle are listed, not counted either way. A settled end the finder does not list is
  put to the finder's own test of an attractor: runs from `FinderConfig.kick_rad` below and
  above it; if neither comes back within `MATCH` it is listed as "not an attractor (kicks slide
  off)", not counted as missed (a settled stretch of a slow saddle passage, or a state whose
  basin is not a neighbourhood in Delta31: 4.580 at 0.655).

Everything goes through the result cache, so the finder's own searches are read back when they
were run before (`reproduce` at the same betas): its runs are the finder's own tasks
(`sim_core.research.probe_task`, `task_runner`). The study is `python -m lab finder-check`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from sim_core import Backend, ModelParams, ResultCache, RunStats, find, run_tasks
from sim_core.contract import TWO_PI, Cell, CellResult, FinderConfig, Probe, settling
from sim_core.research import angle_diff, initial_values, probe_task, task_runner

MATCH = 0.05  # rad, the tolerance
Kick = tuple[float | None, bool]  # where a kick run ended (None: it failed), and if it settled
NUDGE = 0.04  # rad: how far from a reported point its check runs start (finder's kicks: 0.03)
CHECK_DURATION_S = 40.0  # the independent runs


@dataclass
class BetaCheck:
    beta: float
    finder: CellResult
    reached: list[tuple[float, tuple[float | None, float | None], bool]] = field(
        default_factory=list
    )
    # (reported stable point, where its runs from below and above ended (None: unsettled),
    # at least one within MATCH)
    independent: list[tuple[float, float | None, bool]] = field(default_factory=list)
    # (start, settled final or None, found by the finder within MATCH)
    kicked: dict[float, tuple[Kick, Kick]] = field(default_factory=dict)
    # an unlisted settled end -> where its kicks from below and above ended

    def attractor(self, end: float) -> bool:
        """An unlisted end is an attractor if a kick from either side settles back on it (the
        finder lists states that come back from one side only as one-sided states)."""
        kicks = self.kicked.get(end, ((end, True), (end, True)))
        return any(ok and e is not None and _near(e, [end]) for e, ok in kicks)

    def missing(self) -> list[float]:
        """Settled ends the finder does not list that are attractors by its own test."""
        return [
            e for _, e, ok in self.independent if e is not None and not ok and self.attractor(e)
        ]

    @property
    def ok(self) -> bool:
        return all(ok for _, _, ok in self.reached) and not self.missing()


def _near(x: float, points: Sequence[float]) -> bool:
    return any(abs(float(angle_diff(x, p))) <= MATCH for p in points)


def validate(
    betas: Sequence[float],
    cfg: FinderConfig,
    cache: ResultCache,
    backend: Backend,
    params: ModelParams | None = None,
    *,
    starts: int = 8,
    grid: Sequence[float] | None = None,
    progress: bool = True,
    stats: RunStats | None = None,
) -> list[BetaCheck]:
    """The finder over `grid` (default: `betas` alone; each beta's neighbours lend it their
    states, so the grid is part of what is checked) and both checks at `betas`."""
    grid_betas = sorted({*(grid or ()), *betas})
    run = task_runner(cache, backend, params, progress=progress, stats=stats)
    found_all = find([Cell(b) for b in grid_betas], cfg, run)
    by_beta = dict(zip(grid_betas, found_all, strict=True))
    cells = [Cell(b) for b in betas]
    found = [by_beta[b] for b in betas]
    offset = math.pi / starts  # half a spacing: initial_values(starts) + offset
    probes: list[tuple[Cell, Probe, str, float]] = []
    for c, res in zip(cells, found, strict=True):
        for a in res.stable():
            for sign in (-1.0, 1.0):
                x0 = (a.d31 + sign * NUDGE) % (TWO_PI)
                probes.append((c, Probe(x0, CHECK_DURATION_S), "r", a.d31))
        for x in initial_values(starts):
            x0 = float((x + offset) % (TWO_PI))
            probes.append((c, Probe(x0, CHECK_DURATION_S), "i", x0))

    def ends_of(batch: list[tuple[Cell, Probe]]) -> list[Kick]:
        """Where each run ends (None: it failed) and whether it settled, through the cache."""
        tasks = [probe_task(c, p, params) for c, p in batch]
        results, st = run_tasks(tasks, cache, backend, 8, progress)
        if stats is not None:
            stats.computed += st.computed
            stats.cached += st.cached
        out: list[Kick] = []
        for t in tasks:
            r = results[t.key]
            s = settling(r["d31"]) if r["error"] is None else None
            out.append((None, False) if s is None else (s.final, s.settled))
        return out

    checks = {c.beta: BetaCheck(c.beta, res) for c, res in zip(cells, found, strict=True)}
    ends: dict[tuple[float, float], list[float | None]] = {}
    done = ends_of([(c, p) for c, p, _, _ in probes])
    for (c, _, what, x), (final, settled) in zip(probes, done, strict=True):
        end = final if settled else None
        chk = checks[c.beta]
        if what == "r":
            ends.setdefault((c.beta, x), []).append(end)
            if len(ends[c.beta, x]) == 2:
                lo, hi = ends[c.beta, x]
                ok = any(e is not None and _near(e, [x]) for e in (lo, hi))
                chk.reached.append((x, (lo, hi), ok))
        else:
            pts = [a.d31 for a in chk.finder.attractors]
            chk.independent.append((x, end, end is not None and _near(end, pts)))
    # the ends the finder does not list: kicked as the finder kicks its own states
    unlisted = [(c, e) for c in cells for _, e, ok in checks[c.beta].independent
                if e is not None and not ok]  # fmt: skip
    kicks = [(c, e, Probe(float((e + s * cfg.kick_rad) % TWO_PI), CHECK_DURATION_S))
             for c, e in unlisted for s in (-1.0, 1.0)]  # fmt: skip
    back: dict[tuple[float, float], list[Kick]] = {}
    for (c, e, _), kick in zip(kicks, ends_of([(c, p) for c, _, p in kicks]), strict=True):
        back.setdefault((c.beta, e), []).append(kick)
    for (b, e), (below, above) in back.items():
        checks[b].kicked[e] = (below, above)
    return [checks[b] for b in betas]


def _end(e: float | None) -> str:
    return "not settled" if e is None else f"{e:.3f}"


def _said(c: BetaCheck, e: float | None, ok: bool) -> str:
    """An independent run's end as the table says it."""
    if e is None:
        return "not settled"
    if ok:
        return f"{e:.3f}"
    if c.attractor(e):
        return f"{e:.3f} (missing)"
    lo, hi = c.kicked.get(e, ((None, False), (None, False)))
    return f"{e:.3f} (not an attractor: kicks end {_kick(lo)} / {_kick(hi)})"


def _kick(k: Kick) -> str:
    end, settled = k
    if end is None:
        return "failed"
    return f"{end:.3f}" + ("" if settled else " (still drifting)")


def report(checks: Sequence[BetaCheck]) -> list[str]:
    """Markdown table rows: one line per beta."""
    out = ["| β | finder's stable points | one-sided states | reached from 0.04 below / above "
           "| 8 independent 40 s runs (settled finals) | every one found? |",
           "|---|---|---|---|---|---|"]  # fmt: skip

    for c in checks:
        pts = ", ".join(f"{a.d31:.3f}" for a in c.finder.stable()) or "none"
        one = ", ".join(f"{a.d31:.3f} ({a.confirmed})" for a in c.finder.one_sided()) or "none"
        reached = ", ".join(
            f"{x:.3f}→{_end(lo)} / {_end(hi)}{'' if ok else ' **no**'}"
            for x, (lo, hi), ok in c.reached
        )  # fmt: skip
        ends = ", ".join(_said(c, e, ok) for _, e, ok in c.independent)
        out.append(f"| {c.beta:g} | {pts} | {one} | {reached} | {ends} | "
                   f"{'**no**' if c.missing() else 'yes'} |")  # fmt: skip
    return out

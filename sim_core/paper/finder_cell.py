"""One condition's search for the fixed-point finder (`cell_search`): spread starts, the
borders bisected, the kicks, and the record (`CellResult`) made of them. The method and why:
`finder`, whose `find` drives one such search per condition, round by round.
"""

from __future__ import annotations

import math
from collections.abc import Generator
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim_core.contract.finder import (
    Attractor,
    Border,
    Cell,
    CellResult,
    Confirmed,
    FinderConfig,
    Ghost,
    Probe,
    Role,
    RunOutcome,
)
from sim_core.model.gait import (
    TWO_PI,
    Settling,
    angle_diff,
    classify_gait,
    settling,
    wrap,
)
from sim_core.paper.finder_runs import (
    GHOST_LEAVE,
    Cluster,
    clusters_of,
    label_of,
    map_slope,
    parting,
    slowest_passage,
)
from sim_core.paper.returnmap import initial_values

# A bisection run unsettled at full length counts as heading to an attractor when its drift per
# cycle exceeds this (and 3 standard errors): a quarter of the settled rule, so a run that
# lingers at the saddle itself is not forced to a side.
HEADING_DRIFT = 5e-5
# A kick stays inside its state's basin: at most this share of the way to the nearest saddle or
# other state on that side (a kick past the saddle tests nothing about the state).
KICK_ROOM = 0.5
# Kick rounds per condition: states a kick finds are kicked in the next round; left over after
# this many (none seen), a state is reported as confirmed from "neither" side.
MAX_KICK_ROUNDS = 3


@dataclass
class _Run:
    probe: Probe
    role: Role
    d31: list[float]
    settle: Settling
    failure: str | None
    duration_s: float  # simulated: the probe's, or less where it stopped settled
    label: int | None = None  # the attractor it settled on
    side: int | None = None  # in a bisection bracket: the attractor whose side it is on


def _run_of(probe: Probe, role: Role, res: dict[str, Any]) -> _Run:
    failure = res.get("error")
    d31 = [] if failure else list(res["d31"])
    length = res.get("duration_s") or probe.duration_s  # shorter if it stopped settled
    return _Run(probe, role, d31, settling(d31), failure, float(length))


def cell_search(
    cell: Cell, cfg: FinderConfig
) -> Generator[list[Probe], list[dict[str, Any]], CellResult]:
    """One condition's search: yields the probes it needs, receives their results."""
    sim_s = 0.0

    def ask(
        probes: list[Probe],
    ) -> Generator[list[Probe], list[dict[str, Any]], list[dict[str, Any]]]:
        nonlocal sim_s
        out = yield probes
        sim_s += sum(r.get("duration_s") or p.duration_s for p, r in zip(probes, out, strict=True))
        return out

    # a short try that goes on to the full length only where it has not settled
    tries = cfg.bisect_duration_s if cfg.bisect_duration_s < cfg.duration_s else None

    spread = [(float(x), "start") for x in initial_values(cfg.starts)]
    seeds = [(float(wrap(x)), "seed") for x in cell.seeds]
    first: list[tuple[float, Role]] = sorted(spread + seeds)  # type: ignore[arg-type]
    starts = [Probe(x, cfg.duration_s) for x, _ in first]
    outs = yield from ask(starts)
    runs = [_run_of(p, role, r) for p, (_, role), r in zip(starts, first, outs, strict=True)]
    clusters = clusters_of(
        [r.settle.final for r in runs if r.settle.settled and r.settle.final is not None]
    )
    for r in runs:
        if r.settle.settled and r.settle.final is not None:
            r.label = label_of(r.settle.final, clusters)

    # borders: neighbouring starts (on the circle) that end on attractors of different gaits
    gait = [classify_gait(c.value, cell.beta) for c in clusters]
    cand: list[tuple[_Run, _Run]] = []
    n = len(runs)
    for i in range(n):
        a, b = runs[i], runs[(i + 1) % n]
        if a.label is None or b.label is None or a.label == b.label:
            continue
        if gait[a.label] == gait[b.label]:
            continue
        cand.append((a, b))
    lo_w, hi_w = cfg.window

    def inside(pair: tuple[_Run, _Run]) -> int:
        return -sum(lo_w <= clusters[r.label].value <= hi_w for r in pair if r.label is not None)

    cand = sorted(cand, key=inside)[: cfg.max_borders]
    # each border: [lo run, hi run, steps, note, runs placed by their heading]
    for a, b in cand:
        a.side, b.side = a.label, b.label
    brackets: list[list[Any]] = [[a, b, 0, "", 0] for a, b in cand]
    active = [k for k, br in enumerate(brackets) if _width(br) > cfg.border_tol_rad]
    while active:
        probes = [Probe(_mid(brackets[k]), cfg.duration_s, tries) for k in active]
        outs = yield from ask(probes)
        for k, p, res in zip(active, probes, outs, strict=True):
            r = _run_of(p, "bisect", res)
            runs.append(r)
            brackets[k][2] += 1
            if r.settle.settled:
                _narrow(brackets[k], r, clusters)
            elif not _by_heading(brackets[k], r, clusters):
                brackets[k][3] = (
                    f"a run from {p.d31_init:.3f} did not settle in {r.duration_s:g} s "
                    "and heads to neither side"
                )
        active = [
            k for k in active if not brackets[k][3] and _width(brackets[k]) > cfg.border_tol_rad
        ]

    # kicks: each state re-run from either side; new states a kick finds are kicked in turn
    saddles = [_saddle(br) for br in brackets]
    confirmed: dict[int, tuple[Confirmed, tuple[float, float]]] = {}
    for _ in range(MAX_KICK_ROUNDS if cfg.kick_rad > 0 else 0):
        todo = [k for k in range(len(clusters)) if k not in confirmed]
        if not todo:
            break
        sizes = {k: _kick_sizes(k, clusters, saddles, cfg.kick_rad) for k in todo}
        kicks = [(k, side, Probe(float(wrap(clusters[k].value + sign * sizes[k][side])),
                                 cfg.duration_s, tries))
                 for k in todo for side, sign in ((0, -1.0), (1, 1.0))]  # fmt: skip
        outs = yield from ask([p for _, _, p in kicks])
        back = {(k, side): _run_of(p, "kick", res)
                for (k, side, p), res in zip(kicks, outs, strict=True)}  # fmt: skip
        for r in back.values():
            runs.append(r)
            if r.settle.settled and r.settle.final is not None:
                r.label = label_of(r.settle.final, clusters)
                if r.label is None:  # a state no start reached: kicked next round
                    clusters.append(Cluster([r.settle.final]))
                    r.label = len(clusters) - 1
                else:
                    clusters[r.label].finals.append(r.settle.final)
        for k in todo:
            came = [back[k, side].label == k for side in (0, 1)]
            confirmed[k] = (_CONFIRMED[came[0], came[1]], sizes[k])

    # the record
    attractors = []
    for k, c in enumerate(clusters):
        mine = [r for r in runs if r.label == k]
        slope, pairs = map_slope([r.d31 for r in mine], c.value)
        xs = np.unwrap(np.asarray(c.finals))
        how, kicked = confirmed.get(k, ("not checked" if cfg.kick_rad == 0 else "neither", None))
        attractors.append(Attractor(
            d31=c.value, lo=float(wrap(xs.min())), hi=float(wrap(xs.max())),
            gait=classify_gait(c.value, cell.beta),
            starts=sum(1 for r in mine if r.role == "start"), runs=len(mine), slope=slope,
            slope_pairs=pairs, max_drift=max(abs(r.settle.drift or 0.0) for r in mine),
            confirmed=how, kicks=kicked,
        ))  # fmt: skip
    borders = []
    for a, b, steps, note, headed in brackets:
        dwell, growth = parting(a.d31, b.d31)
        if headed:
            note = (note + "; " if note else "") + (
                f"{headed} run(s) near the border placed by where they head (not settled)"
            )
        lo = a.probe.d31_init
        hi = b.probe.d31_init + (TWO_PI if b.probe.d31_init < lo else 0.0)
        borders.append(Border(
            below=a.side, above=b.side, start_lo=lo, start_hi=hi,
            resolved=hi - lo <= cfg.border_tol_rad + 1e-12, d31=dwell, slope=growth,
            steps=steps, note=note,
        ))  # fmt: skip
    ghosts = _ghosts(runs, [a.d31 for a in attractors] + [b.d31 for b in borders if b.d31])
    outcomes = [
        RunOutcome(
            d31_init=r.probe.d31_init, duration_s=r.probe.duration_s,
            stop_if_settled_s=r.probe.stop_if_settled_s, simulated_s=r.duration_s,
            final=r.settle.final,
            drift=r.settle.drift, settled=r.settle.settled, why=r.settle.why,
            attractor=r.label, failure=r.failure, role=r.role,
        )
        for r in runs
    ]  # fmt: skip
    return CellResult(
        beta=cell.beta, body_mass_g=cell.body_mass_g, slope_deg=cell.slope_deg,
        attractors=attractors, borders=borders, ghosts=ghosts, runs=outcomes, sim_s=sim_s,
    )  # fmt: skip


_CONFIRMED: dict[tuple[bool, bool], Confirmed] = {
    (True, True): "both sides", (True, False): "below only", (False, True): "above only",
    (False, False): "neither",
}  # fmt: skip


def _saddle(br: list[Any]) -> float:
    """Where a border's saddle is: its bracketing runs' dwell, else its bracket's middle."""
    dwell, _ = parting(br[0].d31, br[1].d31)
    return _mid(br) if dwell is None else dwell


def _kick_sizes(
    k: int, clusters: list[Cluster], saddles: list[float], kick: float
) -> tuple[float, float]:
    """(below, above): `kick`, or KICK_ROOM of the way to the nearest saddle or other state on
    that side if that is closer, so that a kick tests the state and not its neighbour's basin."""
    x = clusters[k].value
    others = [c.value for j, c in enumerate(clusters) if j != k] + saddles
    d = [float(angle_diff(o, x)) for o in others]
    below = min((-v for v in d if v < 0), default=math.pi)
    above = min((v for v in d if v > 0), default=math.pi)
    return min(kick, KICK_ROOM * below), min(kick, KICK_ROOM * above)


def _width(br: list[Any]) -> float:
    lo, hi = br[0].probe.d31_init, br[1].probe.d31_init
    return float((hi - lo) % TWO_PI)


def _mid(br: list[Any]) -> float:
    return float(wrap(br[0].probe.d31_init + 0.5 * _width(br)))


def _by_heading(br: list[Any], r: _Run, clusters: list[Cluster]) -> bool:
    """A bisection run still unsettled at full length lingers near the saddle: put it on the
    side of the attractor it is heading to (the nearer of the two in the direction of its
    resolved drift), if it clearly heads somewhere. True if it was placed."""
    s = r.settle
    if s.final is None or s.drift is None or s.drift_se is None:
        return False
    if abs(s.drift) < max(HEADING_DRIFT, 3.0 * s.drift_se):
        return False
    options = []
    for side in (0, 1):
        d = float(angle_diff(clusters[br[side].side].value, s.final))
        if d * s.drift > 0:
            options.append((abs(d), side))
    if not options:
        return False
    side = min(options)[1]
    r.side = br[side].side
    br[side] = r
    br[4] += 1
    return True


def _narrow(br: list[Any], r: _Run, clusters: list[Cluster]) -> None:
    """Put a settled bisection run on the side of the bracket whose attractor it reached."""
    assert r.settle.final is not None
    r.label = label_of(r.settle.final, clusters)
    r.side = r.label
    if r.label == br[0].side:
        br[0] = r
    elif r.label == br[1].side:
        br[1] = r
    else:  # a third state between the two: say so and stop this border
        if r.label is None:  # a state no start reached (else it is one the starts found)
            clusters.append(Cluster([r.settle.final]))
            r.label = len(clusters) - 1
        else:
            clusters[r.label].finals.append(r.settle.final)
        br[3] = f"a run from {r.probe.d31_init:.3f} settles on a third state, {r.settle.final:.3f}"


def _ghosts(runs: list[_Run], known: list[float]) -> list[Ghost]:
    """The slowest passage of each run that slides on, away from every attractor and saddle;
    one per place (within GHOST_LEAVE), the slowest kept."""
    found: list[Ghost] = []
    for r in runs:
        if r.failure:
            continue
        g = slowest_passage(r.d31, r.settle.final if r.settle.settled else None)
        if g is None or any(abs(float(angle_diff(g.d31, x))) <= GHOST_LEAVE for x in known):
            continue
        found.append(g.model_copy(update={"d31_init": r.probe.d31_init}))
    out: list[Ghost] = []
    for g in sorted(found, key=lambda g: abs(g.drift)):
        if all(abs(float(angle_diff(g.d31, o.d31))) > GHOST_LEAVE for o in out):
            out.append(g)
    return sorted(out, key=lambda g: g.d31)

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

The search is a set of coroutines, one per condition (`Cell`): each yields the runs it needs
next and receives their results, so every round of every condition goes to the backend as one
batch (`find`). Nothing here simulates: the caller's `run` does (`reproduce` through the
result cache and the local or Dask backend). MuJoCo-free, so the API and the viewer validate
the output schema (`CellResult`) without loading the engine.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Generator, Sequence
from dataclasses import asdict, dataclass, field, replace
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict

from sim_core.model.gait import (
    TWO_PI,
    Settling,
    angle_diff,
    circular_mean,
    classify_gait,
    settling,
    wrap,
)
from sim_core.paper.analysis import FixedPoint, folds, range_ends, stable_ranges
from sim_core.paper.results import AtlasAxis
from sim_core.paper.returnmap import RETURN_MAP_SKIP, initial_values

# Settled finals closer than this (rad) are one attractor: 10x the spread of a settled tail
# (1-4 mrad measured) and 4x below the closest pair of distinct states seen (2.12 / 2.27 at
# beta 0.62).
CLUSTER_TOL = 0.05
# A slowest passage counts as a ghost when Delta31 moves less than this per cycle there (the
# old smoothed-map rule, GHOST_DRIFT in `analysis`) and the run later leaves it by > 0.1 rad.
GHOST_DRIFT = 0.02
GHOST_LEAVE = 0.1
# ... and it spent at least this many cycles within CLUSTER_TOL of it: twice what a passage at
# GHOST_DRIFT needs to cross that 0.1 rad (5), so its mean drift there is below 10 mrad per cycle
GHOST_MIN_CYCLES = 10
# The local drift along a run: Delta31 change over this many cycles, per cycle (the paper's
# lag of 4, twice, so that a period-2 wobble of the skewed tripod averages out).
DRIFT_WINDOW = 8
# Approach pairs within this of an attractor give its map slope (rad); closer than SLOPE_MIN
# they are the settled tail's scatter, not an approach.
SLOPE_RADIUS = 0.3
SLOPE_MIN = 0.005
SLOPE_MIN_PAIRS = 5
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
# Rounds of neighbour seeding along the beta grid (each lends the states the last round found,
# then searches the cells that learnt something again): a state then travels at most this many
# grid steps from where the cell's own runs reached it.
MAX_SEED_ROUNDS = 4
LAG = 4  # the paper's return map: Delta31(n) -> Delta31(n + 4)


@dataclass(frozen=True)
class FinderConfig:
    """How hard the finder looks; each choice measured (docs/NUMERICS.md, "The finder")."""

    starts: int = 8  # spread over the circle (`initial_values`), 0.79 rad apart
    # Measured (beta 0.62-0.70, 8 starts, 40 s): attractors settle (< 0.2 mrad per cycle)
    # within 13-30 s; a tripod start at beta 0.655 sits 15-20 s on its ghost at 2.97 with
    # < 0.05 mrad per cycle before it slides (so 20 s calls it settled, 40 s does not).
    duration_s: float = 40.0
    # Bisection runs only decide a basin between two known attractors; one that has not
    # settled by then goes on to `duration_s` (`Probe.stop_if_settled_s`: one run, not a
    # short try and a re-run from the start).
    bisect_duration_s: float = 20.0
    border_tol_rad: float = 0.02  # the bracket of a border's starts
    # At most this many borders per condition, preferring those in the paper's window: each
    # costs ~6 runs (0.79 -> 0.02 rad).
    max_borders: int = 2
    # Borders are bisected between attractors of different gaits only (classify_gait);
    # two settled states of one gait (e.g. 1.77 / 2.12 at 0.62) are both listed, unbisected.
    window: tuple[float, float] = (1.4, 3.4)  # PAPER_WINDOW
    # Each state is re-run from this far on either side (bisect_duration_s, on to duration_s
    # if unsettled) and is stable only if both come back within CLUSTER_TOL: the issue's
    # "reached from near it" made two-sided. 0.03: a tenth of the smallest basin measured
    # (2.88-2.95 at 0.62 is 0.07 wide; closer saddles shrink the kick, KICK_ROOM). 0: no
    # kicks; every state is then reported as "not checked" (the atlas, to stay in budget).
    kick_rad: float = 0.03
    # Neighbouring betas (same mass and slope) lend the states they found and this beta did
    # not, as extra starts: the state itself and the starts that reached it there. A state with
    # a thin basin that this beta's spread starts miss (4.58 at 0.655, reached at 0.65 from a
    # bisection start 0.59 and at 0.66 from 5.89) is then looked for where it should be.
    neighbour_seeds: bool = True

    @classmethod
    def quick(cls) -> FinderConfig:
        """The machinery on short runs (tests, --quick): nothing here settles by the rule."""
        return cls(starts=3, duration_s=1.5, bisect_duration_s=1.0, border_tol_rad=0.4,
                   max_borders=1, kick_rad=0.0, neighbour_seeds=False)  # fmt: skip


@dataclass(frozen=True)
class Cell:
    """One condition: beta and the physics a RunSpec takes besides the start."""

    beta: float
    body_mass_g: float = 3.0
    slope_deg: float = 0.0
    # extra starts beside the spread ones: where neighbouring conditions found attractors (the
    # atlas), since a start near an attractor that still exists settles at once
    seeds: tuple[float, ...] = ()

    def spec_fields(self) -> dict[str, float]:
        return {"beta": self.beta, "body_mass_g": self.body_mass_g, "slope_deg": self.slope_deg}


@dataclass(frozen=True)
class Probe:
    """One run a search asks for: a start and a duration, at its cell's condition; with
    `stop_if_settled_s`, a short try that runs on to `duration_s` only if it has not settled
    by then (`RunSpec.stop_if_settled_s`: the same numbers as a short run and its re-run)."""

    d31_init: float
    duration_s: float
    stop_if_settled_s: float | None = None

    def spec_fields(self) -> dict[str, float | None]:
        """The RunSpec fields of this run besides its cell's (`Cell.spec_fields`)."""
        return {"d31_init": self.d31_init, "duration_s": self.duration_s,
                "stop_if_settled_s": self.stop_if_settled_s}  # fmt: skip


# --- the output schema (what reproduce, the REST kinds and the viewer read) --------------------
class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


Role = Literal["start", "seed", "bisect", "kick"]
# How a state's kicks came back: from both sides (stable), from one side only (it attracts
# from below or above only: semi-stable, or the edge of a slowly drifting band), from neither
# (only its own start reached it), or not kicked (FinderConfig.kick_rad = 0).
Confirmed = Literal["both sides", "below only", "above only", "neither", "not checked"]


class RunOutcome(_Model):
    """One settled-or-not run of the search."""

    d31_init: float
    duration_s: float  # asked for (the probe's)
    final: float | None  # circular mean of the last quarter (rad)
    drift: float | None  # rad per gait cycle over the last quarter
    settled: bool
    why: str  # why not settled ("" if settled)
    attractor: int | None  # index into CellResult.attractors, None if unsettled or failed
    failure: str | None = None
    role: Role = "start"
    stop_if_settled_s: float | None = None  # the probe's short try, if it had one
    simulated_s: float | None = None  # how long it ran: less than duration_s if it stopped

    def probe(self) -> Probe:
        """The probe that ran it (its task, `search.probe_task`, reads its series back)."""
        return Probe(self.d31_init, self.duration_s, self.stop_if_settled_s)


class Attractor(_Model):
    """A stable gait: where settled runs end (finals within CLUSTER_TOL)."""

    d31: float  # circular mean of its runs' finals, rad
    lo: float  # lowest and highest final (a spread > 0 is a flat band, or slow drift)
    hi: float
    gait: str  # classify_gait of d31
    starts: int  # how many of the spread starts end here (seeds not counted)
    runs: int  # all runs that end here (starts and bisection)
    slope: float | None  # of the n -> n+4 map at it, from its runs' approach (< 1: attracts)
    slope_pairs: int
    max_drift: float  # largest |drift| per cycle of its runs' settled tails
    confirmed: Confirmed = "not checked"
    kicks: tuple[float, float] | None = None  # the kicks' sizes below and above, rad

    @property
    def stable(self) -> bool:
        """A stable gait: its kicks came back from both sides, or it was not kicked."""
        return self.confirmed in ("both sides", "not checked")


class Border(_Model):
    """An unstable gait: the border between two basins, by bisection of the start."""

    below: int  # attractor reached from the lower start of the bracket
    above: int  # ... from the upper start
    start_lo: float  # the bracket of starts, rad (start_hi may exceed 2 pi: on the circle)
    start_hi: float
    resolved: bool  # bracket narrower than the finder's border_tol_rad
    d31: float | None  # where the bracketing runs dwell before they part (the saddle), rad
    slope: float | None  # growth of their separation per 4 cycles (> 1: repels)
    steps: int  # bisection runs made
    note: str = ""


class Ghost(_Model):
    """A slowest passage: a run slides on through here, slowly."""

    d31: float
    drift: float  # rad per cycle at the slowest point (signed)
    cycles: int  # cycles the run spent within CLUSTER_TOL of it
    d31_init: float  # the run that shows it


class CellResult(_Model):
    """Everything the finder knows about one condition."""

    beta: float
    body_mass_g: float
    slope_deg: float
    attractors: list[Attractor]
    borders: list[Border]
    ghosts: list[Ghost]
    runs: list[RunOutcome]
    sim_s: float  # simulated seconds spent

    @property
    def unsettled(self) -> list[RunOutcome]:
        """Runs that did not settle and were not re-run longer from the same start (a short
        try that was re-run longer is a screen, not a finding; since the finder's tries go on
        in one run, `Probe.stop_if_settled_s`, this matters for outputs written before)."""
        longest: dict[tuple[float, str], float] = {}
        for r in self.runs:
            key = (r.d31_init, r.role)
            longest[key] = max(longest.get(key, 0.0), r.duration_s)
        return [
            r
            for r in self.runs
            if not r.settled and r.failure is None and r.duration_s >= longest[(r.d31_init, r.role)]
        ]

    def stable(self, gait: str | None = None) -> list[Attractor]:
        """The stable states (`Attractor.stable`), of one gait if given."""
        return [a for a in self.attractors if a.stable and (gait is None or a.gait == gait)]

    def one_sided(self) -> list[Attractor]:
        """Settled states that kicks did not confirm from both sides."""
        return [a for a in self.attractors if not a.stable]

    def pattern(self, window: tuple[float, float] = (1.4, 3.4)) -> str:
        """'S U S'-style, in order of Delta31 inside `window`: the paper's Fig. 7 reading."""
        pts = [(a.d31, "S") for a in self.stable()]
        pts += [(b.d31, "U") for b in self.borders if b.d31 is not None]
        return " ".join(s for x, s in sorted(pts) if window[0] <= x <= window[1])


class FinderOutput(_Model):
    """The finder over a set of conditions: the one data file Figs. 7-8, the REST
    `bifurcation` and `atlas` kinds and the viewer's panels read."""

    source: str
    config: dict[str, Any]
    cells: list[CellResult]


# --- pure analyses of one run's series ---------------------------------------------------------
def local_drift(
    d31: np.ndarray | Sequence[float], window: int = DRIFT_WINDOW
) -> tuple[np.ndarray, np.ndarray]:
    """(Delta31 at the middle of each window, drift per cycle across it) along one run."""
    d = np.unwrap(np.asarray(d31, dtype=float)[RETURN_MAP_SKIP:])
    if d.size <= window:
        return np.empty(0), np.empty(0)
    drift = (d[window:] - d[:-window]) / window
    mid = wrap(0.5 * (d[window:] + d[:-window]))
    return mid, drift


def slowest_passage(d31: Sequence[float], final: float | None) -> Ghost | None:
    """The run's slowest point away from where it ends (a ghost), or None."""
    mid, drift = local_drift(d31)
    if mid.size == 0:
        return None
    away = (
        np.ones(mid.size, bool) if final is None else np.abs(angle_diff(mid, final)) > GHOST_LEAVE
    )
    # only the part before the run last came within GHOST_LEAVE of its end
    if final is not None:
        near = np.nonzero(~away)[0]
        if near.size:
            away[near[0] :] = False
    else:  # still moving at its end: only what it did before its last quarter
        away[-max(1, mid.size // 4) :] = False
    if not away.any():
        return None
    k = int(np.argmin(np.where(away, np.abs(drift), np.inf)))
    if abs(drift[k]) >= GHOST_DRIFT:
        return None
    cycles = int(np.sum(np.abs(angle_diff(mid, mid[k])) <= CLUSTER_TOL))
    if cycles < GHOST_MIN_CYCLES:
        return None
    return Ghost(d31=float(mid[k]), drift=float(drift[k]), cycles=cycles, d31_init=math.nan)


def map_slope(series: Sequence[Sequence[float]], x_star: float) -> tuple[float | None, int]:
    """Slope of the n -> n+LAG map at x_star, least squares through (x_star, x_star) over the
    approach pairs of `series` within SLOPE_MIN..SLOPE_RADIUS of it."""
    us: list[np.ndarray] = []
    vs: list[np.ndarray] = []
    for s in series:
        d = np.asarray(s, dtype=float)[RETURN_MAP_SKIP:]
        if d.size <= LAG:
            continue
        u, v = angle_diff(d[:-LAG], x_star), angle_diff(d[LAG:], x_star)
        sel = (np.abs(u) >= SLOPE_MIN) & (np.abs(u) <= SLOPE_RADIUS)
        us.append(u[sel])
        vs.append(v[sel])
    u = np.concatenate(us) if us else np.empty(0)
    v = np.concatenate(vs) if vs else np.empty(0)
    if u.size < SLOPE_MIN_PAIRS:
        return None, int(u.size)
    return float(u @ v / (u @ u)), int(u.size)


def parting(a: Sequence[float], b: Sequence[float]) -> tuple[float | None, float | None]:
    """Two runs that start on either side of a border: (where they dwell together before they
    part, growth of their separation per LAG cycles while it is 0.01-0.3 rad)."""
    x = np.asarray(a, dtype=float)[RETURN_MAP_SKIP:]
    y = np.asarray(b, dtype=float)[RETURN_MAP_SKIP:]
    n = min(x.size, y.size)
    if n <= LAG:
        return None, None
    x, y = x[:n], y[:n]
    sep = np.abs(angle_diff(x, y))
    together = np.nonzero(sep <= CLUSTER_TOL)[0]
    dwell = None
    if together.size:
        upto = together[-1] + 1  # until they last were together
        mids = np.unwrap(x[:upto]) + 0.5 * angle_diff(y[:upto], x[:upto])
        _, drift = local_drift(np.concatenate([[0.0] * RETURN_MAP_SKIP, wrap(mids)]))
        if drift.size:
            k = int(np.argmin(np.abs(drift)))
            dwell = float(wrap(mids[min(k + DRIFT_WINDOW // 2, upto - 1)]))
        else:
            dwell = circular_mean(wrap(mids))
    growth = [
        sep[k + LAG] / sep[k]
        for k in range(n - LAG)
        if 0.01 <= sep[k] <= 0.3 and sep[k + LAG] <= 0.6
    ]
    return dwell, (float(np.median(growth)) if growth else None)


# --- the search --------------------------------------------------------------------------------
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


@dataclass
class _Cluster:
    finals: list[float] = field(default_factory=list)

    @property
    def value(self) -> float:
        return circular_mean(self.finals)


def _run_of(probe: Probe, role: Role, res: dict[str, Any]) -> _Run:
    failure = res.get("error")
    d31 = [] if failure else list(res["d31"])
    length = res.get("duration_s") or probe.duration_s  # shorter if it stopped settled
    return _Run(probe, role, d31, settling(d31), failure, float(length))


def _clusters(finals: list[float]) -> list[_Cluster]:
    """Group settled finals on the circle: neighbours closer than CLUSTER_TOL chain together."""
    if not finals:
        return []
    xs = sorted(float(wrap(f)) for f in finals)
    groups = [[xs[0]]]
    for x in xs[1:]:
        if x - groups[-1][-1] <= CLUSTER_TOL:
            groups[-1].append(x)
        else:
            groups.append([x])
    if len(groups) > 1 and xs[0] + TWO_PI - xs[-1] <= CLUSTER_TOL:  # across the wrap
        groups[0] = groups.pop() + groups[0]
    return [_Cluster(g) for g in groups]


def cluster_finals(finals: Sequence[float]) -> list[tuple[float, int]]:
    """(circular mean, count) of each group of settled finals (`_clusters`' rule)."""
    return [(c.value, len(c.finals)) for c in _clusters(list(finals))]


def _label(x: float, clusters: list[_Cluster]) -> int | None:
    for k, c in enumerate(clusters):
        if min(abs(float(angle_diff(x, f))) for f in c.finals) <= CLUSTER_TOL:
            return k
    return None


def _search(
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
    clusters = _clusters(
        [r.settle.final for r in runs if r.settle.settled and r.settle.final is not None]
    )
    for r in runs:
        if r.settle.settled and r.settle.final is not None:
            r.label = _label(r.settle.final, clusters)

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
                r.label = _label(r.settle.final, clusters)
                if r.label is None:  # a state no start reached: kicked next round
                    clusters.append(_Cluster([r.settle.final]))
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
    k: int, clusters: list[_Cluster], saddles: list[float], kick: float
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


def _by_heading(br: list[Any], r: _Run, clusters: list[_Cluster]) -> bool:
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


def _narrow(br: list[Any], r: _Run, clusters: list[_Cluster]) -> None:
    """Put a settled bisection run on the side of the bracket whose attractor it reached."""
    assert r.settle.final is not None
    r.label = _label(r.settle.final, clusters)
    r.side = r.label
    if r.label == br[0].side:
        br[0] = r
    elif r.label == br[1].side:
        br[1] = r
    else:  # a third state between the two: say so and stop this border
        if r.label is None:  # a state no start reached (else it is one the starts found)
            clusters.append(_Cluster([r.settle.final]))
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


RunFn = Callable[[list[tuple[Cell, Probe]]], list[dict[str, Any]]]


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
    searches = {k: _search(cells[k], cfg) for k in which}
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


def branch_ranges(cells: Sequence[CellResult], gait: str) -> dict[str, Any]:
    """Where `gait` has an attractor along a beta grid: ranges, their ends and the folds
    between (beta of the last point on each branch, +- half the grid step)."""
    betas = [c.beta for c in cells]
    fixed = [[FixedPoint(a.d31, a.slope or 0.0, True) for a in c.stable()] for c in cells]
    rng = stable_ranges(betas, fixed, gait)
    return {"ranges": rng, "ends": range_ends(betas, rng),
            "folds": [asdict(f) for f in folds(betas, rng, gait)]}  # fmt: skip


# --- the gait atlas's schema (`sim_core.paper.atlas` writes it; the REST kind and the viewer
# read it) ---------------------------------------------------------------------------------------
AXIS_PARAM: dict[str, str] = {"mass": "body_mass_g", "slope": "slope_deg"}
AXIS_LABEL: dict[str, str] = {"mass": "body mass (g)", "slope": "slope (deg, uphill +)"}
Region = Literal["both", "tripod only", "metachronal only", "other states", "not settled"]
REGIONS: tuple[str, ...] = ("both", "tripod only", "metachronal only", "other states",
                            "not settled")  # fmt: skip


def region_of(cell: CellResult) -> Region:
    """Which of the paper's two gaits are stable at one condition (classify_gait of each
    stable state); 'not settled' when no run settled at all."""
    gaits = {a.gait for a in cell.stable()}
    if "tripod" in gaits and "metachronal" in gaits:
        return "both"
    if "tripod" in gaits:
        return "tripod only"
    if "metachronal" in gaits:
        return "metachronal only"
    return "other states" if cell.attractors else "not settled"


class AtlasFold(_Model):
    """Where a gait's stable range along beta ends, at one value of the other axis."""

    gait: str
    value: float
    side: str  # "upper": the gait lives below this beta; "lower": above it
    beta: float
    half_width: float


class AtlasOutput(_Model):
    """The finder over a beta x (body mass | slope) grid: regions, attractors, fold lines."""

    source: str
    axis: AtlasAxis
    param: str  # the RunSpec field of the axis: body_mass_g or slope_deg
    betas: list[float]
    values: list[float]
    cells: list[CellResult]  # value-major: cells[i * len(betas) + j] is (values[i], betas[j])
    regions: list[list[Region]]  # [value][beta]
    folds: list[AtlasFold]
    sweep_beta: float  # the paper's Fig. 9 sweeps run at this beta ...
    sweep_range: tuple[float, float]  # ... over this range of the axis (ours, `ReproduceConfig`)
    paper_direction: str
    config: dict[str, Any]

    def cell(self, value_index: int, beta_index: int) -> CellResult:
        return self.cells[value_index * len(self.betas) + beta_index]

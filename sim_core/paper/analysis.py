"""Reading the paper's quantities out of simulated data: pure functions, tested on synthetic data.

Transition detection, and what Figs. 6-9 need on top: stable ranges and folds of a
bifurcation diagram (from the fixed-point finder's attractors, `contract.finder`), and the
two legs of a triangle sweep with their transitions and the hysteresis loop between them.
Angles in rad; the swept value in the units of the parameter being swept.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from sim_core.contract.finder import CellResult
from sim_core.contract.summaries import SweepSummary, SweepTransition
from sim_core.model.gait import angle_diff, classify_gait, window_gait

# The band of Delta31 the paper's return maps and bifurcation diagram are about (branches 1.9
# and 2.9 rad, with margin). A continuous map of the circle crosses its diagonal an even number
# of times; the paper's odd counts (1, 3, 1) are the crossings inside this band.
PAPER_WINDOW = (1.4, 3.4)
# Consecutive leg-1 touchdowns (strides) a new gait must hold to count as a transition.
PERSIST = 4


@dataclass(frozen=True)
class FixedPoint:
    """A fixed point of the n -> n + 4 map (the finder's attractors and saddles)."""

    d31: float  # rad
    slope: float  # of the lag-cycle map Delta31(n) -> Delta31(n + lag) at the point
    stable: bool


@dataclass(frozen=True)
class Transition:
    value: float  # the ramped parameter where the gait switched
    time_s: float
    before: str
    after: str


def detect_transitions(
    values: np.ndarray, d31: np.ndarray, betas: np.ndarray, persist: int = 4
) -> list[Transition]:
    """Where the classified gait (`classify_gait` at each sample's beta) switches and then
    stays switched for `persist` samples.

    'other' samples (in between the branches) never start or end a gait; the switch is placed
    at the first sample of the new gait.
    """
    gaits = [classify_gait(float(x), float(b)) for x, b in zip(d31, betas, strict=True)]
    out: list[Transition] = []
    current: str | None = None
    k = 0
    while k < len(gaits):
        g = gaits[k]
        if g == "other" or g == current:
            k += 1
            continue
        run = gaits[k : k + persist]
        if len(run) == persist and all(x == g for x in run):
            if current is not None:
                out.append(Transition(float(values[k]), float(k), current, g))
            current = g
            k += persist
        else:
            k += 1
    return out


def stable_ranges(
    betas: Sequence[float], fixed: Sequence[Sequence[FixedPoint]], gait: str
) -> list[tuple[float, float]]:
    """Contiguous runs of grid betas with a stable fixed point of `gait` (classify_gait)."""
    has = [
        any(f.stable and classify_gait(f.d31, b) == gait for f in fps)
        for b, fps in zip(betas, fixed, strict=True)
    ]
    out: list[tuple[float, float]] = []
    start: float | None = None
    for k, (b, h) in enumerate(zip(betas, has, strict=True)):
        if h and start is None:
            start = b
        if start is not None and (not h or k == len(betas) - 1):
            out.append((start, b if h else betas[k - 1]))
            start = None
    return out


@dataclass(frozen=True)
class Fold:
    """Where a stable branch ends inside the grid: between two grid betas (value = midpoint)."""

    gait: str
    side: str  # "upper": the branch exists below; "lower": it exists above
    beta: float
    half_width: float  # the fold lies within beta +- half_width


def folds(betas: Sequence[float], ranges: Sequence[tuple[float, float]], gait: str) -> list[Fold]:
    """The ends of each stable range that lie inside the grid (grid edges are not folds)."""
    grid = list(betas)
    out: list[Fold] = []
    for lo, hi in ranges:
        i, j = grid.index(lo), grid.index(hi)
        if i > 0:
            out.append(Fold(gait, "lower", 0.5 * (grid[i - 1] + lo), 0.5 * (lo - grid[i - 1])))
        if j < len(grid) - 1:
            out.append(Fold(gait, "upper", 0.5 * (hi + grid[j + 1]), 0.5 * (grid[j + 1] - hi)))
    return out


def range_ends(
    betas: Sequence[float], ranges: Sequence[tuple[float, float]]
) -> tuple[float, float] | None:
    """(lower, upper) end of the single stable range, each a grid edge or a fold midpoint."""
    if len(ranges) != 1:
        return None
    lo, hi = ranges[0]
    grid = list(betas)
    i, j = grid.index(lo), grid.index(hi)
    lower = lo if i == 0 else 0.5 * (grid[i - 1] + lo)
    upper = hi if j == len(grid) - 1 else 0.5 * (hi + grid[j + 1])
    return lower, upper


def branch_ranges(cells: Sequence[CellResult], gait: str) -> dict[str, Any]:
    """Where `gait` has an attractor along a beta grid: ranges, their ends and the folds
    between (beta of the last point on each branch, +- half the grid step)."""
    betas = [c.beta for c in cells]
    fixed = [[FixedPoint(a.d31, a.slope or 0.0, True) for a in c.stable()] for c in cells]
    rng = stable_ranges(betas, fixed, gait)
    return {"ranges": rng, "ends": range_ends(betas, rng),
            "folds": [asdict(f) for f in folds(betas, rng, gait)]}  # fmt: skip


def _transition(t: Transition, times: np.ndarray) -> SweepTransition:
    k = int(t.time_s)  # detect_transitions stores the sample index there
    return SweepTransition(value=t.value, time_s=float(times[k]), before=t.before, after=t.after)


def sweep_summary(
    times_s: Sequence[float],
    values: Sequence[float],
    d31: Sequence[float],
    start: float,
    turn: float,
    hold_s: float,
    ramp_s: float,
    beta: Sequence[float] | float,
    persist: int = PERSIST,
) -> dict[str, Any]:
    """Transitions on each leg of a triangle sweep start -> turn -> start, and the loop.

    Transitions are detected on the whole series (so the second leg knows the gait it starts
    in) and assigned to a leg by time; switches during the first hold are settling, not
    transitions. `loop` is True when the first leg's switch lies beyond the second leg's in
    the first leg's direction: the system stayed on its branch both ways (hysteresis).
    `beta`: the duty factor at each sample (the values, when beta is swept) or a constant.
    Returned as plain data (what the cache and `reproduce` keep), its keys and types those of
    the contract's `SweepSummary`, which builds it.
    """
    t = np.asarray(times_s, dtype=float)
    v = np.asarray(values, dtype=float)
    d = np.asarray(d31, dtype=float)
    turn_t = hold_s + ramp_s
    b = np.broadcast_to(np.asarray(beta, dtype=float), d.shape)
    found = detect_transitions(v, d, b, persist) if d.size else []
    legs: dict[str, list[SweepTransition]] = {"first": [], "second": []}
    for tr in found:
        item = _transition(tr, t)
        if item.time_s < hold_s:
            continue
        legs["first" if item.time_s < turn_t else "second"].append(item)
    sign = 1.0 if turn > start else -1.0
    width: float | None = None
    loop: bool | None = None
    if legs["first"] and legs["second"]:
        v1, v2 = legs["first"][0].value, legs["second"][0].value
        width = float(abs(v1 - v2))
        loop = bool((v1 - v2) * sign > 0)
    return SweepSummary(
        start=start,
        turn=turn,
        first_leg=legs["first"],
        second_leg=legs["second"],
        width=width,
        loop=loop,
        gait_at_start=_gait_until(d, b, t < hold_s),
        gait_at_turn=_gait_until(d, b, t < turn_t),
        gait_at_end=_gait_until(d, b, np.ones(d.shape, dtype=bool)),
    ).model_dump()


def _gait_until(d31: np.ndarray, beta: np.ndarray, upto: np.ndarray) -> str:
    """`window_gait` of the samples in `upto` (a leading stretch), at its last beta."""
    d = d31[upto]
    return window_gait(d, float(beta[upto][-1])) if d.size else "other"


def branch_census(finals: Sequence[float | None], target: float, tol: float) -> tuple[int, int]:
    """(runs whose settled Delta31 is within `tol` of `target`, runs counted)."""
    hit = sum(1 for f in finals if f is not None and abs(float(angle_diff(f, target))) <= tol)
    return hit, len(finals)


def max_drift(series: Sequence[Sequence[float]]) -> float:
    """Largest |Delta31_k - Delta31_0| over all samples of all series (rad, on the circle)."""
    worst = 0.0
    for s in series:
        d = np.asarray(s, dtype=float)
        if d.size:
            worst = max(worst, float(np.max(np.abs(angle_diff(d, d[0])))))
    return worst if math.isfinite(worst) else math.inf

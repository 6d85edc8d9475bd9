"""The paper's experiment protocols: quasi-static ramps (Figs. 6, 9), return-map fixed points
(Fig. 7) and the bifurcation diagram (Fig. 8), as functions over the public runner.

Analysis is separate from simulation so that it can be tested on synthetic data with known
answers: `fixed_points` finds where a drift curve crosses zero on the circle and classifies
stability from the slope of the 4-cycle map there; `detect_transitions` finds where a ramp's
Delta31 changes branch.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from sim_core.calibration import ReturnMap, initial_values, return_map
from sim_core.gait import TWO_PI, classify_gait
from sim_core.params import ModelParams
from sim_core.runner import BatchRunner
from sim_core.spec import RunSpec


@dataclass(frozen=True)
class FixedPoint:
    d31: float  # rad
    slope: float  # of the lag-cycle map Delta31(n) -> Delta31(n + lag) at the point
    stable: bool


def fixed_points(centers: np.ndarray, drift: np.ndarray, lag: int = 4) -> list[FixedPoint]:
    """Zero crossings of a periodic drift-per-cycle curve d(x) sampled at `centers`.

    The lag-cycle map is F(x) = x + lag d(x); a crossing is stable when |F'| < 1 there
    (paper Sec. III C). Only crossings between two neighbouring sampled (finite) bins count;
    the curve wraps around 2 pi.
    """
    x = np.asarray(centers, dtype=float)
    d = np.asarray(drift, dtype=float)
    out: list[FixedPoint] = []
    n = x.size
    for i in range(n):
        j = (i + 1) % n
        d0, d1 = d[i], d[j]
        if not (np.isfinite(d0) and np.isfinite(d1)):
            continue  # only neighbouring sampled bins: no crossing invented across a gap
        x0, x1 = x[i], x[j] + (TWO_PI if j == 0 else 0.0)
        if d0 == 0.0 or (d0 > 0) != (d1 > 0):
            if d0 == d1:
                continue
            root = x0 + (x1 - x0) * d0 / (d0 - d1)
            slope = 1.0 + lag * (d1 - d0) / (x1 - x0)
            out.append(FixedPoint(float(root % TWO_PI), float(slope), abs(slope) < 1.0))
    return sorted(out, key=lambda f: f.d31)


def map_fixed_points(rm: ReturnMap, bins: int = 24) -> list[FixedPoint]:
    centers, drift = rm.drift_per_cycle(bins)
    return fixed_points(centers, drift, rm.lag)


@dataclass(frozen=True)
class BifurcationPoint:
    beta: float
    fixed: list[FixedPoint]


def bifurcation(
    betas: Sequence[float],
    params: ModelParams | None = None,
    n_init: int = 24,
    duration_s: float = 3.0,
    bins: int = 24,
) -> list[BifurcationPoint]:
    """Stable and unstable fixed points of the return map for each beta (Fig. 8)."""
    inits = initial_values(n_init).tolist()
    out = []
    for b in betas:
        rm = return_map(params, b, inits, duration_s=duration_s)
        out.append(BifurcationPoint(b, map_fixed_points(rm, bins)))
    return out


@dataclass(frozen=True)
class Ramp:
    """A quasi-static ramp: the swept value and Delta31 at each leg-1 touchdown."""

    name: str
    time_s: np.ndarray
    value: np.ndarray
    d31: np.ndarray
    error: str | None


Schedule = Callable[[float], float]


def ramp(
    name: str,
    schedule: Schedule,
    duration_s: float,
    start: RunSpec,
    params: ModelParams | None = None,
) -> Ramp:
    """Run one simulation while `schedule(t)` sets beta, body_mass_g or slope_deg live."""
    setters = {
        "beta": BatchRunner.set_beta,
        "body_mass_g": BatchRunner.set_body_mass_g,
        "slope_deg": BatchRunner.set_slope_deg,
    }
    if name not in setters:
        raise ValueError(f"cannot ramp {name!r}; choose from {sorted(setters)}")
    runner = BatchRunner([start.model_copy(update={"duration_s": duration_s})], params, nthread=1)
    setter = setters[name]
    value_at: list[float] = []
    last = math.nan
    while runner.active[0]:
        v = float(schedule(runner.time))
        if v != last:
            setter(runner, 0, v)
            last = v
        n_before = len(runner.d31_v[0])
        runner.step_block()
        if len(runner.d31_v[0]) > n_before:
            value_at.append(v)
    return Ramp(
        name=name,
        time_s=np.array(runner.d31_t[0]),
        value=np.array(value_at),
        d31=np.array(runner.d31_v[0]),
        error=runner.errors[0],
    )


def triangle(start: float, turn: float, hold_s: float, ramp_s: float) -> Schedule:
    """Hold `start`, ramp linearly to `turn` and back in `ramp_s` each way (Fig. 6a protocol)."""

    def value(t: float) -> float:
        if t < hold_s:
            return start
        u = t - hold_s
        if u < ramp_s:
            return start + (turn - start) * u / ramp_s
        u -= ramp_s
        if u < ramp_s:
            return turn + (start - turn) * u / ramp_s
        return start

    return value


@dataclass(frozen=True)
class Transition:
    value: float  # the ramped parameter where the gait switched
    time_s: float
    before: str
    after: str


def detect_transitions(values: np.ndarray, d31: np.ndarray, persist: int = 4) -> list[Transition]:
    """Where the classified gait switches and then stays switched for `persist` samples.

    'other' samples (in between the branches) never start or end a gait; the switch is placed
    at the first sample of the new gait.
    """
    gaits = [classify_gait(float(x)) for x in d31]
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


def hysteresis_width(ramp_down: list[Transition], ramp_up: list[Transition]) -> float | None:
    """Distance between the first switch of each direction (the loop's width), if both exist."""
    if not ramp_down or not ramp_up:
        return None
    return abs(ramp_down[0].value - ramp_up[0].value)

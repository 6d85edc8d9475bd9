"""What the finder reads off its runs. Off one run's Delta31 series (at leg-1 touchdowns): the
local drift along it, its slowest passage (a ghost), the slope of the n -> n+4 map at a state
from the approach to it, and where two runs that start either side of a border dwell before
they part (the saddle). Off many runs: their settled finals clustered into states. Pure numpy,
tested on synthetic data; the search (`finder`) calls them, and the surface atlas's walks
(`surface_walks`) cluster their finals by the same rule.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from sim_core.contract.finder import CLUSTER_TOL, Ghost
from sim_core.contract.returnmap import RETURN_MAP_SKIP
from sim_core.model.gait import TWO_PI, angle_diff, circular_mean, wrap

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
LAG = 4  # the paper's return map: Delta31(n) -> Delta31(n + 4)


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


# --- many runs' finals, clustered on the circle ---------------------------------------------
@dataclass
class Cluster:
    """Settled finals that are one state (`clusters_of`); the state is their circular mean."""

    finals: list[float] = field(default_factory=list)

    @property
    def value(self) -> float:
        return circular_mean(self.finals)


def clusters_of(finals: list[float]) -> list[Cluster]:
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
    return [Cluster(g) for g in groups]


def cluster_finals(finals: Sequence[float]) -> list[tuple[float, int]]:
    """(circular mean, count) of each group of settled finals (`clusters_of`' rule)."""
    return [(c.value, len(c.finals)) for c in clusters_of(list(finals))]


def label_of(x: float, clusters: list[Cluster]) -> int | None:
    """The index of the cluster `x` belongs to (within CLUSTER_TOL of one of its finals)."""
    for k, c in enumerate(clusters):
        if min(abs(float(angle_diff(x, f))) for f in c.finals) <= CLUSTER_TOL:
            return k
    return None

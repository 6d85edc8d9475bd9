"""The divergence guard's per-control-period test, compiled: it runs after every control period
of every simulation, and as numpy ops it cost ~21 us per period for one simulation (~8% of a
single run's wall time); compiled it is a few microseconds.

Besides numerical trouble it checks physical sanity (`sim_core.model.spec` states each
threshold and its reason): the body left the ground, no leg has a foothold, the body slides
backwards. Those checks read the state and write only their own bookkeeping (`Footing`), so a
run that passes them is bit-identical to one that was never checked.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

OK = 0
WARNED = 1  # a MuJoCo instability warning: MuJoCo has reset the state, so it is garbage
NON_FINITE = 2
FLIPPED = 3
ON_FLOOR = 4
LEFT_GROUND = 5
NO_FOOTHOLDS = 6
SLIDING_BACK = 7


class Limits(NamedTuple):
    """The guard's thresholds (floats), in SI units."""

    min_height: float  # m, body centre above the floor: below it the box lies on the floor
    min_up_cos: float  # z of the body's up axis: below it the body has flipped
    reach: float  # m, a leg's reach from its coxa attachment (`anatomy.leg_reach`)
    no_foothold_s: float  # s with no leg in stance
    slide_window_s: float  # s over which the forward velocity is averaged
    slide_speed: float  # m/s, backwards, averaged over the window


class Footing(NamedTuple):
    """Per simulation, the guard's own bookkeeping for the physical checks."""

    x_ref: np.ndarray  # (n,) body x at the start of the current sliding window, m
    t_ref: np.ndarray  # (n,) time the current window started, s
    t_foothold: np.ndarray  # (n,) last time a leg was in stance, s


def new_footing(n: int) -> Footing:
    return Footing(np.zeros(n), np.zeros(n), np.zeros(n))


@njit(cache=True)
def up_axis_z(quat: np.ndarray) -> float:
    """z component of the body's up axis for a unit quaternion (w, x, y, z)."""
    return 1.0 - 2.0 * (quat[1] ** 2 + quat[2] ** 2)


@njit(cache=True)
def lowest_point_z(qpos: np.ndarray, points: np.ndarray) -> float:
    """World z of the lowest of `points` (body frame, (k, 3)) for a free body's qpos[0:7]."""
    w, x, y, z = qpos[3], qpos[4], qpos[5], qpos[6]
    r0 = 2.0 * (x * z - w * y)
    r1 = 2.0 * (y * z + w * x)
    r2 = 1.0 - 2.0 * (x * x + y * y)
    low = np.inf
    for k in range(points.shape[0]):
        h = qpos[2] + r0 * points[k, 0] + r1 * points[k, 1] + r2 * points[k, 2]
        low = min(low, h)
    return low


@njit(cache=True)
def guard_codes(
    ids: np.ndarray,
    qpos: np.ndarray,
    qvel: np.ndarray,
    warnings: np.ndarray,
    warn_seen: np.ndarray,
    stance: np.ndarray,
    time: float,
    attach: np.ndarray,
    limits: Limits,
    footing: Footing,
    codes: np.ndarray,
    values: np.ndarray,
) -> int:
    """codes[r] for simulation ids[r] (values[r]: the measure that failed, for the message);
    warn_seen and `footing` are updated. Returns how many simulations failed (the caller's loop
    over failures runs only then).

    Priority when several hold: warning, non-finite, flipped, on the floor, left the ground,
    no footholds, sliding back.
    """
    failed = 0
    for r in range(ids.size):
        s = ids[r]
        warned = False
        for k in range(warnings.shape[1]):
            if warnings[s, k, 1] > warn_seen[s, k]:
                warned = True
            warn_seen[s, k] = warnings[s, k, 1]
        finite = np.isfinite(qpos[s]).all() and np.isfinite(qvel[s]).all()
        code = OK
        if warned:
            code = WARNED
        elif not finite:
            code = NON_FINITE
        elif up_axis_z(qpos[s, 3:7]) < limits.min_up_cos:
            code = FLIPPED
        elif qpos[s, 2] < limits.min_height:
            code = ON_FLOOR
        else:
            low = lowest_point_z(qpos[s], attach)
            if low > limits.reach:
                code = LEFT_GROUND
                values[r] = low
            if stance[s].any():
                footing.t_foothold[s] = time
            elif code == OK and time - footing.t_foothold[s] > limits.no_foothold_s - 1e-12:
                code = NO_FOOTHOLDS
                values[r] = time - footing.t_foothold[s]
            span = time - footing.t_ref[s]
            if span > limits.slide_window_s - 1e-12:
                v = (qpos[s, 0] - footing.x_ref[s]) / span
                if code == OK and v < -limits.slide_speed:
                    code = SLIDING_BACK
                    values[r] = v
                footing.x_ref[s] = qpos[s, 0]
                footing.t_ref[s] = time
        codes[r] = code
        if code != OK:
            failed += 1
    return failed

"""The divergence guard's per-control-period test, compiled: it runs after every control period
of every simulation, and as numpy ops it cost ~21 us per period for one simulation (~8% of a
single run's wall time); compiled it is a few microseconds."""

from __future__ import annotations

import numpy as np
from numba import njit

OK = 0
WARNED = 1  # a MuJoCo instability warning: MuJoCo has reset the state, so it is garbage
NON_FINITE = 2
FLIPPED = 3
ON_FLOOR = 4


@njit(cache=True)
def up_axis_z(quat: np.ndarray) -> float:
    """z component of the body's up axis for a unit quaternion (w, x, y, z)."""
    return 1.0 - 2.0 * (quat[1] ** 2 + quat[2] ** 2)


@njit(cache=True)
def guard_codes(
    ids: np.ndarray,
    qpos: np.ndarray,
    qvel: np.ndarray,
    warnings: np.ndarray,
    warn_seen: np.ndarray,
    min_height: float,
    min_up_cos: float,
    codes: np.ndarray,
) -> int:
    """codes[r] for simulation ids[r]; warn_seen is updated to the new counts. Returns how
    many simulations failed (the caller's loop over failures runs only then).

    Priority when several hold: warning, non-finite, flipped, on the floor.
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
        if warned:
            codes[r] = WARNED
        elif not finite:
            codes[r] = NON_FINITE
        elif up_axis_z(qpos[s, 3:7]) < min_up_cos:
            codes[r] = FLIPPED
        elif qpos[s, 2] < min_height:
            codes[r] = ON_FLOOR
        else:
            codes[r] = OK
        if codes[r] != OK:
            failed += 1
    return failed

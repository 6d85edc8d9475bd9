"""Open-loop probes: what the touchdowns would do to Delta31, with Delta31 held fixed.

With phase resetting off, Delta31 stays where it was put, so every probe walks one known gait;
the mean phase jump e_i that leg i's touchdowns would cause gives the return map's drift per
gait cycle there (`gait.drift_per_cycle`). Cheap, deterministic, and well conditioned where
the map is nearly neutral: calibration objectives score its sign, and the numerics grid its
error against a converged reference.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from sim_core.model.gait import drift_per_cycle, phase_jumps
from sim_core.model.params import Integrator, ModelParams, phi_aep
from sim_core.model.runner import simulate_batch
from sim_core.model.spec import spec_grid


def open_loop_drift(
    params: ModelParams | None,
    *,
    betas: Sequence[float],
    d31s: Sequence[float],
    duration_s: float,
    settle_s: float,
    integrator: Integrator | None = None,
    dt_s: float | None = None,
    control_dt_s: float | None = None,
    nthread: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Drift per gait cycle the touchdowns would cause at each (beta, Delta31), resets off.

    Args:
        params: model parameters (defaults if None).
        betas: duty factors, (nb,).
        d31s: the held Delta31 values, rad, (nd,).
        duration_s: simulated time of each probe, s.
        settle_s: touchdowns before this time are ignored (the start-up transient), s.
        integrator, dt_s, control_dt_s: numerics (model defaults if None).
        nthread: threads for the batch (0: all cores).

    Returns:
        (drift (nb, nd) rad per cycle, jumps (nb, nd, 6) rad); NaN where a probe failed.
    """
    specs = spec_grid(betas, d31s, duration_s=duration_s, phase_reset=False,
                      integrator=integrator, dt_s=dt_s, control_dt_s=control_dt_s)  # fmt: skip
    jumps = np.full((len(specs), 6), np.nan)
    for k, (spec, res) in enumerate(
        zip(specs, simulate_batch(specs, params, nthread=nthread), strict=True)
    ):
        if not res.diverged:
            jumps[k] = phase_jumps(
                res.events.touchdowns_s, res.events.touchdown_phases, phi_aep(spec.beta), settle_s
            )
    grid = jumps.reshape(len(betas), len(d31s), 6)
    return drift_per_cycle(grid), grid

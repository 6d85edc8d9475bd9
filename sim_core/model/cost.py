"""What a run costs before it runs (physics steps, recorded samples, memory) and the bounds on
that cost, so that a request that could only exhaust the machine is refused at the door.

MuJoCo-free (`sim_core.contract` re-exports it): the CLI and the REST API refuse with the same
numbers and the same sentences (`sim_core.model.spec.cost_problem`). The byte counts were
measured with tracemalloc on the worker's own path (`server.kinds.execute`, then `json.dumps`)
at beta 0.66, 1 and 3 s, one and two runs; they are estimates, rounded up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

# record period of the time series, s (footfall resolution: 6% of T_sw)
RECORD_DT_S = 2e-3

# The smallest physics step a run may take: a tenth of the finest step the model ever needed
# (RK4 at 1e-5 s is the converged reference of docs/NUMERICS.md); finer buys no accuracy, only
# time, and at 1e-12 s the runner's per-period buffers alone asked for 67 GiB.
MIN_DT_S = 1e-6
# Physics steps (duration_s / dt_s) one run may take: the longest run (600 s) at the reference
# step 1e-5 s, which admits every integrator at its measured stable limit for 600 s. Measured
# 24.5 us per implicitfast step on the 2-core development machine: ~25 min (RK4 ~4x that).
MAX_STEPS_PER_RUN = 60_000_000
# Memory one job may hold while it runs and stores its result: 2 GiB, a tenth of the 23 GiB
# development machine, so that a few workers, the API and the viewer fit beside one another.
MAX_JOB_BYTES = 2 * 1024**3

# per recorded sample (every RECORD_DT_S) of one run: the recorder's row (94 B of numpy), the
# result's copy of it and the events (touchdowns, lift-offs) that grow beside it; measured
# 110-150 B (55-75 kB per simulated second)
RECORD_BYTES = 200
# the same sample kept as a series (`include_series`): Python lists in the result, a row dict
# in the samples table and the JSON text; measured 1.4-1.6 MB per simulated second = 2.8-3.3 kB
SERIES_RECORD_BYTES = 3_400
# the runner's foot-position buffer per physics step of one control period (6 foot sites x 3
# coordinates x float64): what blew up at dt_s 1e-12 s (5e8 steps per 5e-4 s period)
SUBSTEP_BYTES = 6 * 3 * 8
# fixed per run: MuJoCo's data, the controller's state, the result's summary (measured 0.3 MB)
RUN_BYTES = 300_000


@dataclass(frozen=True)
class RunCost:
    """What one run will take: physics steps, recorded samples, bytes held."""

    steps: int
    records: int
    bytes: int


def run_cost(
    duration_s: float, dt_s: float, control_dt_s: float, *, series: bool = False
) -> RunCost:
    """The cost of one run at resolved numerics (`resolve_numerics`: dt, control period).

    Args:
        duration_s: simulated time, s.
        dt_s: physics step, s; control_dt_s: controller period, s (a whole number of steps).
        series: the run's time series is kept as JSON-able lists (`include_series`).
    """
    periods = math.ceil(duration_s / control_dt_s - 1e-9)
    substeps = max(1, round(control_dt_s / dt_s))
    every = max(1, round(RECORD_DT_S / control_dt_s))
    records = math.ceil(duration_s / (every * control_dt_s)) + 2
    per_record = RECORD_BYTES + (SERIES_RECORD_BYTES if series else 0)
    nbytes = RUN_BYTES + records * per_record + substeps * SUBSTEP_BYTES
    return RunCost(steps=periods * substeps, records=records, bytes=nbytes)


def gib(nbytes: float) -> str:
    return f"{nbytes / 1024**3:.2g} GiB"

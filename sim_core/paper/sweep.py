"""The paper's quasi-static sweep (Figs. 6a and 9) as one public call.

A sweep holds a parameter (beta, body mass or slope) at `start`, ramps it linearly to `turn`
and back, and records Delta31 at every leg-1 touchdown with the value the parameter had then.
It runs exactly as `insect-gait reproduce` runs its ramps (one `Task`, `execute_chunk`), so the
REST service's hysteresis jobs and the reproduction report see the same numbers. (The viewer's
demo ramp is a live triangle from the slider's position, `web/controls.BetaRamp`, on the same
`Simulation` engine: the same physics, not the same schedule.)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from sim_core.model.params import ModelParams
from sim_core.model.ramp import RAMP_PARAMS, Ramp, RampParam
from sim_core.model.spec import RunFailure, RunSpec
from sim_core.paper.analysis import sweep_summary
from sim_core.runs.backends import Backend, Executor, InlineBackend, RunStats, run_tasks
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import execute_chunk, ramp_task


@dataclass(frozen=True)
class SweepResult:
    """Delta31 along a down/up (or up/down) sweep of one parameter.

    Attributes:
        parameter: the swept RunSpec field (`beta`, `body_mass_g` or `slope_deg`).
        times_s: (n,) time of each leg-1 touchdown, s.
        values: (n,) the swept parameter at each touchdown, in its RunSpec unit.
        d31: (n,) Delta31 at each touchdown, rad in [0, 2 pi).
        summary: transitions on each leg of the sweep, the loop's width and whether it is a
            hysteresis loop (`sim_core.paper.analysis.sweep_summary`).
        failure: why the run stopped early (divergence, a fall), or None.
    """

    parameter: str
    times_s: list[float]
    values: list[float]
    d31: list[float]
    summary: dict[str, Any]
    failure: RunFailure | None

    @property
    def error(self) -> str | None:
        return None if self.failure is None else str(self.failure)


def sweep(
    start: RunSpec,
    *,
    parameter: RampParam,
    turn: float,
    hold_s: float,
    ramp_s: float,
    params: ModelParams | None = None,
    progress: Callable[[float], None] | None = None,
    cache: ResultCache | None = None,
    backend: Backend | None = None,
    stats: RunStats | None = None,
    executor: Executor = execute_chunk,
) -> SweepResult:
    """Hold `start`'s value of `parameter` for `hold_s`, ramp to `turn` in `ramp_s`, back in
    `ramp_s`, hold again; `start.duration_s` is replaced by the schedule's length.

    Args:
        start: the run's spec; its `parameter` field is the sweep's start value.
        parameter: `beta`, `body_mass_g` or `slope_deg`.
        turn: the value the sweep turns at (same unit as the field).
        hold_s: seconds held at the start value before and after the ramps.
        ramp_s: seconds for each ramp leg.
        params: model parameters (defaults if None).
        progress: called with the share of the sweep done (0..1), about every 1% (with a
            cache: when the run is done; `executor` may report inside it).
        cache, backend: where the run's result is kept and read back (None: nowhere, the run
            is computed here) and where it runs (None: in this process); `stats`, if given,
            counts it as computed or read from the cache; `executor` runs it
            (`execute_chunk`), as in `run_tasks`.

    Raises:
        ValueError: an unknown parameter, or a start or turn value outside RunSpec's range.
    """
    if parameter not in RAMP_PARAMS:
        raise ValueError(f"cannot sweep {parameter!r}; choose from {list(RAMP_PARAMS)}")
    begin = float(getattr(start, parameter))
    ramp = Ramp(param=parameter, start=begin, turn=turn, hold_s=hold_s, ramp_s=ramp_s)
    task = ramp_task(ramp, start, params)
    if cache is None:
        (res,) = execute_chunk([task], progress)
    else:
        results, st = run_tasks([task], cache, backend or InlineBackend(), progress=False,
                                executor=executor, on_progress=progress)  # fmt: skip
        if stats is not None:
            stats.add(st)
        res = results[task.key]
    summary = sweep_summary(
        res["d31_times_s"],
        res["value"],
        res["d31"],
        begin,
        turn,
        hold_s,
        ramp_s,
        res["value"] if parameter == "beta" else start.beta,
    )
    return SweepResult(
        parameter=parameter,
        times_s=list(res["d31_times_s"]),
        values=list(res["value"]),
        d31=list(res["d31"]),
        summary=summary,
        failure=None if res["failure"] is None else RunFailure(**res["failure"]),
    )

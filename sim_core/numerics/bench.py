"""`insect-gait bench`: speed of the default configuration and of the paper's RK4 at 0.02 ms,
for each ground (MuJoCo's constraint contact, the default; the paper's penalty ground), measured
side by side in one run (ratios mean something only within one run on one machine)."""

from __future__ import annotations

import os
import time
from typing import Any

import numpy as np

from sim_core.model.gait import TWO_PI
from sim_core.model.params import ModelParams
from sim_core.model.runner import BatchRunner
from sim_core.model.spec import RunSpec

PAPER_INTEGRATOR = "rk4"
PAPER_DT = 2e-5


def single_rate(spec: RunSpec, params: ModelParams | None = None) -> tuple[float, float]:
    """(simulated s per wall s, controller share of step time) for one simulation."""
    runner = BatchRunner([spec], params, nthread=1)
    runner.run(max_blocks=1)  # compile/warm up outside the clock
    for k in runner.timers:
        runner.timers[k] = 0.0
    t0 = time.perf_counter()
    runner.run()
    wall = time.perf_counter() - t0
    share = runner.timers["controller"] / max(sum(runner.timers.values()), 1e-12)
    return (runner.time - runner.control_dt) / wall, share


def _batch(spec: RunSpec, nsim: int, params: ModelParams | None = None) -> float:
    specs = [
        spec.model_copy(update={"d31_init": float(x)})
        for x in np.linspace(0, TWO_PI, nsim, endpoint=False)
    ]
    runner = BatchRunner(specs, params, nthread=0)
    runner.run(max_blocks=1)
    t0 = time.perf_counter()
    runner.run()
    wall = time.perf_counter() - t0
    return nsim * (runner.time - runner.control_dt) / wall


def run_bench(sim_seconds: float = 2.0, nsim: int = 32, verbose: bool = True) -> dict[str, Any]:
    p = ModelParams()
    default = RunSpec(beta=0.66, d31_init=2.5, duration_s=sim_seconds)
    paper = default.model_copy(update={"integrator": PAPER_INTEGRATOR, "dt_s": PAPER_DT})
    single_rtf, share = single_rate(default)
    batch_rate = _batch(default, nsim)
    rk4_rtf, rk4_share = single_rate(paper)
    penalty = ModelParams.of(ground="penalty")
    pen_rtf, pen_share = single_rate(default, penalty)
    pen_batch = _batch(default, nsim, penalty)
    pen_rk4_rtf, _ = single_rate(paper, penalty)
    report = {
        "integrator": p.numerics.integrator,
        "dt_s": p.numerics.dt,
        "control_dt_s": p.numerics.control_dt,
        "single_realtime_factor": single_rtf,
        "batch_sim_s_per_wall_s": batch_rate,
        "batch_size": nsim,
        "threads": os.cpu_count(),
        "controller_share": share,
        "rk4_single_realtime_factor": rk4_rtf,
        "rk4_controller_share": rk4_share,
        "speedup_vs_rk4": single_rtf / rk4_rtf,
        "penalty_single_realtime_factor": pen_rtf,
        "penalty_batch_sim_s_per_wall_s": pen_batch,
        "penalty_controller_share": pen_share,
        "penalty_rk4_single_realtime_factor": pen_rk4_rtf,
        "penalty_vs_default": pen_rtf / single_rtf,
        "penalty_vs_rk4": pen_rtf / rk4_rtf,
        "penalty_vs_penalty_rk4": pen_rtf / pen_rk4_rtf,
    }
    if verbose:
        print(
            f"default: {p.numerics.integrator} dt {p.numerics.dt:g} s, "
            f"control every {p.numerics.control_dt:g} s"
        )
        print(f"{'':22s}{'constraint ground':>20s}{'penalty ground':>18s}")
        print(f"{'one simulation':22s}{single_rtf:14.2f} x rt{pen_rtf:12.2f} x rt")
        print(f"{'batch of ' + str(nsim):22s}{batch_rate:12.2f} sim-s/s{pen_batch:10.2f} sim-s/s")
        print(f"{'controller share':22s}{100 * share:15.1f} %{100 * pen_share:15.1f} %")
        print(f"{'paper: rk4 dt 2e-05 s':22s}{rk4_rtf:14.2f} x rt{pen_rk4_rtf:12.2f} x rt")
        print(f"default / paper rk4     {single_rtf / rk4_rtf:6.2f} x faster (constraint ground)")
        print(f"penalty / default       {pen_rtf / single_rtf:6.2f} x faster (same step)")
        print(f"penalty / paper rk4     {pen_rtf / rk4_rtf:6.2f} x faster (rk4 on the constraint "
              f"ground), {pen_rtf / pen_rk4_rtf:.2f} x (rk4 on the penalty ground)")  # fmt: skip
    return report

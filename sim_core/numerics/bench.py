"""`insect-gait bench`: speed of the default configuration and of the paper's RK4 at 0.02 ms,
measured side by side in one run (ratios mean something only within one run on one machine)."""

from __future__ import annotations

import os
import time
from typing import Any

import numpy as np

from sim_core.model.params import ModelParams
from sim_core.model.runner import BatchRunner
from sim_core.model.spec import RunSpec

PAPER_INTEGRATOR = "rk4"
PAPER_DT = 2e-5


def _single(spec: RunSpec) -> tuple[float, float]:
    """(simulated s per wall s, controller share of step time) for one simulation."""
    runner = BatchRunner([spec], nthread=1)
    runner.run(max_blocks=1)  # compile/warm up outside the clock
    for k in runner.timers:
        runner.timers[k] = 0.0
    t0 = time.perf_counter()
    runner.run()
    wall = time.perf_counter() - t0
    share = runner.timers["controller"] / max(sum(runner.timers.values()), 1e-12)
    return (runner.time - runner.control_dt) / wall, share


def _batch(spec: RunSpec, nsim: int) -> float:
    specs = [
        spec.model_copy(update={"d31_init": float(x)})
        for x in np.linspace(0, 2 * np.pi, nsim, endpoint=False)
    ]
    runner = BatchRunner(specs, nthread=0)
    runner.run(max_blocks=1)
    t0 = time.perf_counter()
    runner.run()
    wall = time.perf_counter() - t0
    return nsim * (runner.time - runner.control_dt) / wall


def run_bench(sim_seconds: float = 2.0, nsim: int = 32, verbose: bool = True) -> dict[str, Any]:
    p = ModelParams()
    default = RunSpec(beta=0.66, d31_init=2.5, duration_s=sim_seconds)
    paper = default.model_copy(update={"integrator": PAPER_INTEGRATOR, "dt_s": PAPER_DT})
    single_rtf, share = _single(default)
    batch_rate = _batch(default, nsim)
    rk4_rtf, rk4_share = _single(paper)
    report = {
        "integrator": p.integrator,
        "dt_s": p.dt,
        "control_dt_s": p.control_dt,
        "single_realtime_factor": single_rtf,
        "batch_sim_s_per_wall_s": batch_rate,
        "batch_size": nsim,
        "threads": os.cpu_count(),
        "controller_share": share,
        "rk4_single_realtime_factor": rk4_rtf,
        "rk4_controller_share": rk4_share,
        "speedup_vs_rk4": single_rtf / rk4_rtf,
    }
    if verbose:
        print(f"default: {p.integrator} dt {p.dt:g} s, control every {p.control_dt:g} s")
        print(f"  one simulation      {single_rtf:6.2f} x real time")
        print(f"  batch of {nsim:<3d}        {batch_rate:6.2f} simulated s per wall s")
        print(f"  controller share    {100 * share:6.1f} % of step time")
        print(f"paper: {PAPER_INTEGRATOR} dt {PAPER_DT:g} s")
        print(f"  one simulation      {rk4_rtf:6.2f} x real time")
        print(f"default / paper       {single_rtf / rk4_rtf:6.2f} x faster")
    return report

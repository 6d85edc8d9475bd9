"""A paper-like toy system standing in for the simulator in the reproduce tests.

Delta31 follows a one-dimensional map, one step per stride: x <- x + g(x) + c(beta), with
g(x) = -A (x - 1.9)(x - 2.4)(x - 2.9) (stable points at 1.9 and 2.9 rad, unstable at 2.4) and
a tilt c(beta) proportional to 0.6575 - beta so that the metachronal pair meets in a fold at beta =
0.645 and the tripod pair at beta = 0.67: the paper's Fig. 8 by construction. Body mass and
slope act through an effective beta (heavier or uphill -> lower beta -> tripod), and without
phase resetting Delta31 does not move; held by the pin (`RunSpec.pin_d31`) its touchdowns' jumps
carry the drift at the held value. `fake_execute` has the signature of
`sim_core.runs.tasks.execute_chunk`, so the whole reproduce pipeline runs on it in milliseconds.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from sim_core.contract.finder import Cell, Probe
from sim_core.model.params import phi_aep
from sim_core.paper.search import probe_task
from sim_core.runs.tasks import Task

A = 0.4
# the cubic's local extrema are +-A * 0.25 / (3 sqrt 3); the tilt reaches them 0.0125 either
# side of 0.6575 (the folds) and saturates at 1.5 times that, so the branches stay near 1.9, 2.9
EXTREMUM = A * 0.25 / (3 * math.sqrt(3))
MAX_STEP = 0.3  # rad per stride, far from the band


def tilt(beta: float) -> float:
    return EXTREMUM * float(np.clip((0.6575 - beta) / 0.0125, -1.5, 1.5))


def drift(x: float, beta: float) -> float:
    g = -A * (x - 1.9) * (x - 2.4) * (x - 2.9) + tilt(beta)
    return float(np.clip(g, -MAX_STEP, MAX_STEP))


def effective_beta(task: Task, value: float | None) -> float:
    spec = task.run_spec()
    beta, mass, slope = spec.beta, spec.body_mass_g, spec.slope_deg
    if task.ramp is not None and value is not None:
        if task.ramp.param == "beta":
            beta = value
        elif task.ramp.param == "body_mass_g":
            mass = value
        else:
            slope = value
    return beta + 0.01 * (3.0 - mass) - 0.0015 * slope


def pinned_run(task: Task) -> dict[str, Any]:
    """A walk held at Delta31 = D (`RunSpec.pin_d31`): every stride the fore legs land g(D)
    late and the hind legs g(D) early, so the drift per cycle read from the jumps
    (`gait.drift_per_cycle`) is the toy's own drift at D."""
    spec = task.run_spec()
    d = float(spec.pin_d31 or 0.0)
    g = drift(d, effective_beta(task, None))
    aep = phi_aep(spec.beta)
    jumps = (-g, -g, 0.0, 0.0, g, g)
    times = list(np.arange(0.034, spec.duration_s, 0.034 / (1.0 - spec.beta)))
    return {
        "d31": [d] * len(times), "d31_times_s": times, "d31_final": d, "gait": "other",
        "error": None, "failure": None, "compute_s": 0.0,
        "touchdowns_s": [times for _ in range(6)],
        "touchdown_phases": [[aep - e] * len(times) for e in jumps],
    }  # fmt: skip


def fake_run(task: Task) -> dict[str, Any]:
    spec = task.run_spec()
    if spec.pin_d31 is not None:
        return pinned_run(task)
    sched = None if task.ramp is None else task.ramp.schedule()
    x, t = spec.d31_init, 0.0
    times: list[float] = []
    d31: list[float] = []
    values: list[float] = []
    ramps_beta = task.ramp is not None and task.ramp.param == "beta"
    while True:
        commanded = float(sched(t)) if sched is not None and ramps_beta else spec.beta
        t += 0.034 / (1.0 - commanded)  # one stride, T = T_sw / (1 - beta)
        if t > spec.duration_s:
            break
        value = None if sched is None else float(sched(t))
        beta = effective_beta(task, value)
        if spec.phase_reset:
            x = (x + drift(x, beta)) % (2 * math.pi)
        times.append(t)
        d31.append(x)
        if value is not None:
            values.append(value)
    out: dict[str, Any] = {
        "d31": d31, "d31_times_s": times, "d31_final": d31[-1] if d31 else None, "gait": "other",
        "speed_cm_s": 100 * (1 - spec.beta) * 2e-3 / (spec.beta * 0.034), "slip_fraction": 0.0,
        "error": None, "compute_s": 0.0,
    }  # fmt: skip
    if sched is not None:
        out["value"] = values
        out["touchdowns_s"] = [[s + 0.01 * leg for s in times] for leg in range(6)]
        out["liftoffs_s"] = [[s + 0.05 + 0.01 * leg for s in times] for leg in range(6)]
    return out


def fake_execute(tasks: Sequence[Task]) -> list[dict[str, Any]]:
    return [fake_run(t) for t in tasks]


def fake_runner(batch: Sequence[tuple[Cell, Probe]]) -> list[dict[str, Any]]:
    """The finder's `run` on the toy (`sim_core.paper.finder.find`)."""
    return [fake_run(probe_task(c, p, None)) for c, p in batch]

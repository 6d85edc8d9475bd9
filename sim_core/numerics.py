"""Is a numerical setting converged? Same gait outcomes at a timestep and at half of it.

Gait selection is decided by touchdown events, so convergence is judged on outcomes: the
Delta31 each initial value ends at, compared between dt and dt/2 (control period unchanged),
run by run. A run that settles on a branch at one timestep and elsewhere at the other, or
diverges at one only, is a disagreement whatever its numbers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sim_core.gait import angle_diff
from sim_core.params import Integrator, ModelParams
from sim_core.runner import simulate_batch
from sim_core.spec import RunSpec

TOLERANCE_RAD = 0.05  # the tolerance on Delta31 outcomes


@dataclass(frozen=True)
class ConvergenceRow:
    beta: float
    d31_init: float
    final_dt: float | None
    final_half: float | None
    gait_dt: str | None
    gait_half: str | None

    @property
    def difference(self) -> float:
        if self.final_dt is None or self.final_half is None:
            return math.inf if (self.final_dt is None) != (self.final_half is None) else 0.0
        return abs(float(angle_diff(self.final_dt, self.final_half)))


@dataclass(frozen=True)
class ConvergenceReport:
    integrator: str
    dt_s: float
    control_dt_s: float
    duration_s: float
    rows: list[ConvergenceRow]

    def agree(self, tol: float = TOLERANCE_RAD) -> list[bool]:
        return [r.difference <= tol and r.gait_dt == r.gait_half for r in self.rows]

    def summary(self, tol: float = TOLERANCE_RAD) -> str:
        ok = self.agree(tol)
        lines = [
            f"{self.integrator} dt {self.dt_s:g} s vs {self.dt_s / 2:g} s, control "
            f"{self.control_dt_s:g} s, {self.duration_s:g} s runs: {sum(ok)}/{len(ok)} agree "
            f"within {tol} rad"
        ]
        for r, good in zip(self.rows, ok, strict=True):
            f1 = "div" if r.final_dt is None else f"{r.final_dt:.3f}"
            f2 = "div" if r.final_half is None else f"{r.final_half:.3f}"
            lines.append(
                f"  beta {r.beta:.3f} init {r.d31_init:.2f}: {f1} ({r.gait_dt}) vs {f2} "
                f"({r.gait_half})  |diff| {r.difference:.3f} {'ok' if good else 'DIFFERS'}"
            )
        return "\n".join(lines)


def convergence_check(
    params: ModelParams | None = None,
    betas: Sequence[float] = (0.62, 0.655, 0.70),
    inits: Sequence[float] = tuple(np.linspace(0, 2 * math.pi, 8, endpoint=False) + math.pi / 8),
    duration_s: float = 6.0,
    dt_s: float | None = None,
    integrator: Integrator | None = None,
    nthread: int = 0,
) -> ConvergenceReport:
    p = params or ModelParams()
    dt = dt_s or p.dt
    integ = integrator or p.integrator
    control = max(p.control_dt, dt)

    def specs(step: float) -> list[RunSpec]:
        return [
            RunSpec(
                beta=b,
                d31_init=float(x),
                duration_s=duration_s,
                dt_s=step,
                control_dt_s=control,
                integrator=integ,
            )
            for b in betas
            for x in inits
        ]

    coarse = simulate_batch(specs(dt), p, nthread=nthread)
    fine = simulate_batch(specs(dt / 2), p, nthread=nthread)
    rows = []
    for spec, a, b in zip(specs(dt), coarse, fine, strict=True):
        rows.append(
            ConvergenceRow(
                beta=spec.beta,
                d31_init=spec.d31_init,
                final_dt=a.d31_final,
                final_half=b.d31_final,
                gait_dt=a.gait,
                gait_half=b.gait,
            )
        )
    return ConvergenceReport(integ, dt, control, duration_s, rows)

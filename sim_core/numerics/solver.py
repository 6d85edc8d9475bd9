"""The constraint solver's options, side by side: what each costs and what it changes.

Every option runs the default integrator and timestep on the grid's starts (the same specs as
`grid_study`) and is measured three ways in one run: its cost (wall s per simulated s, one
simulation on one thread), its outcome error against the paper's RK4 at 2e-5 s with the same
option (the numerics tolerance: every Delta31 within 0.05 rad, the same gaits), and its
distance from today's default run by run; plus the return map's drift error against the
converged reference, the well-conditioned rate (docs/NUMERICS.md, "Tolerance"). An option may
become the default only if it stays within the tolerance and is faster; then `reproduce` is
re-run and the physics version bumped.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from sim_core.model.params import ModelParams
from sim_core.model.runner import simulate_batch
from sim_core.model.spec import RunSpec, spec_grid
from sim_core.numerics.convergence import (
    DRIFT_D31,
    DRIFT_REFERENCE,
    REFERENCE,
    TOLERANCE_RAD,
    drift_rates,
    same_gaits,
    worst_error,
)

# (label, ModelParams overrides): MuJoCo's solver options and the controller period
SOLVER_OPTIONS: tuple[tuple[str, dict[str, object]], ...] = (
    ("default (newton, 100 iterations, elliptic, warm start)", {}),
    ("newton, at most 10 iterations", {"solver_iterations": 10}),
    ("newton, at most 5 iterations", {"solver_iterations": 5}),
    ("newton, at most 3 iterations", {"solver_iterations": 3}),
    ("cg", {"solver": "cg"}),
    ("pgs", {"solver": "pgs"}),
    ("pyramidal cone", {"cone": "pyramidal"}),
    ("no warm start", {"warmstart": False}),
    ("tolerance 1e-5", {"solver_tolerance": 1e-5}),
    ("controller period 1e-3 s", {"control_dt": 1e-3}),
)


@dataclass(frozen=True)
class OptionRow:
    label: str
    wall_per_sim_s: float  # one simulation, one thread
    error_rad: float | None  # worst |Delta31 - RK4 2e-5 s with the same option|; None: failed
    same_gaits: bool
    from_default_rad: float | None  # worst |Delta31 - today's default|, run by run
    drift_error: float | None  # worst |drift per cycle - converged reference|, rad/cycle
    failure: str | None

    @property
    def within_tolerance(self) -> bool:
        return (
            self.failure is None
            and self.error_rad is not None
            and self.error_rad <= TOLERANCE_RAD
            and self.same_gaits
        )


def solver_options_study(
    options: Sequence[tuple[str, dict[str, object]]] = SOLVER_OPTIONS,
    *,
    betas: Sequence[float] = (0.62, 0.70),
    inits: Sequence[float] = (1.0, 1.8, 2.75),
    duration_s: float = 3.0,
    params: ModelParams | None = None,
    progress: Callable[[str], None] | None = None,
) -> tuple[list[OptionRow], dict[str, object]]:
    base = params or ModelParams()

    def specs(p: ModelParams, integrator: str, dt: float) -> list[RunSpec]:
        return spec_grid(betas, inits, duration_s=duration_s, integrator=integrator, dt_s=dt,
                         control_dt_s=max(p.numerics.control_dt, dt))  # fmt: skip

    ref_drift = drift_rates(*DRIFT_REFERENCE, params=base, betas=betas, d31s=DRIFT_D31)
    info: dict[str, object] = {
        "betas": list(betas),
        "inits": list(inits),
        "duration_s": duration_s,
        "reference": list(REFERENCE),
        "drift_reference": list(DRIFT_REFERENCE),
    }
    rows: list[OptionRow] = []
    default_finals: list[float | None] | None = None
    for label, over in options:
        p = base.replace(**over) if over else base
        t0 = time.perf_counter()
        runs = simulate_batch(specs(p, p.numerics.integrator, p.numerics.dt), p, nthread=1)
        wall = (time.perf_counter() - t0) / (duration_s * len(runs))
        failed = [r.failure for r in runs if r.failure is not None]
        if failed:
            row = OptionRow(label, wall, None, False, None, None, failed[0].kind)
        else:
            finals = [r.measures.d31_final for r in runs]
            if default_finals is None:
                default_finals = finals
            ref = [r.measures.d31_final for r in simulate_batch(specs(p, *REFERENCE), p)]
            drift = drift_rates(
                p.numerics.integrator, p.numerics.dt, params=p, betas=betas, d31s=DRIFT_D31
            )
            err = float(np.max(np.abs(drift - ref_drift)))
            row = OptionRow(
                label,
                wall,
                worst_error(finals, ref),
                same_gaits(finals, ref, [r.spec.beta for r in runs]),
                worst_error(finals, default_finals),
                None if math.isnan(err) else err,
                None,
            )
        rows.append(row)
        if progress is not None:
            progress(option_line(row, rows[0].wall_per_sim_s))
    return rows, info


def _f(v: float | None, fmt: str) -> str:
    return "-" if v is None else fmt.format(v)


def option_line(row: OptionRow, default_wall: float) -> str:
    verdict = "within tolerance" if row.within_tolerance else (row.failure or "outside tolerance")
    return (
        f"{row.label:55s} {default_wall / row.wall_per_sim_s:5.2f}x the default's speed, "
        f"error {_f(row.error_rad, '{:.3f}')} rad, from default "
        f"{_f(row.from_default_rad, '{:.3f}')} rad, drift error "
        f"{_f(row.drift_error, '{:.4f}')} rad/cycle: {verdict}"
    )


def options_markdown(rows: Sequence[OptionRow]) -> str:
    """The table NUMERICS.md shows: each option's speed and outcome error, side by side."""
    base = rows[0].wall_per_sim_s
    lines = [
        "| option | speed vs default | wall s per sim s | error vs RK4 2e-5 s (rad) | same "
        "gaits | from default (rad) | drift error (rad/cycle) | verdict |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        verdict = "ok" if r.within_tolerance else (r.failure or "outside tolerance")
        lines.append(
            f"| {r.label} | {base / r.wall_per_sim_s:.2f}x | {r.wall_per_sim_s:.3f} | "
            f"{_f(r.error_rad, '{:.3f}')} | {'yes' if r.same_gaits else 'no'} | "
            f"{_f(r.from_default_rad, '{:.3f}')} | {_f(r.drift_error, '{:.4f}')} | {verdict} |"
        )
    return "\n".join(lines)

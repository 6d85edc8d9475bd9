"""Is a numerical setting converged? Same gait outcomes at a timestep and at half of it.

Gait selection is decided by touchdown events, so convergence is judged on outcomes: the
Delta31 each initial value ends at, compared between dt and dt/2 (control period unchanged),
run by run. A run that settles on a branch at one timestep and elsewhere at the other, or
diverges at one only, is a disagreement whatever its numbers.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim_core.model.gait import TWO_PI, angle_diff, classify_gait
from sim_core.model.params import Integrator, ModelParams
from sim_core.model.probes import open_loop_drift
from sim_core.model.runner import simulate_batch
from sim_core.model.spec import RunSpec, spec_grid

TOLERANCE_RAD = 0.05  # the tolerance on Delta31 outcomes
# Where the return map's drift is probed (rad): just below the metachronal branch and across the
# slow, nearly neutral region above it, where walking is regular. Not lower: near Delta31 = 1
# (legs 1, 3 and 5 nearly in phase) landings are irregular and the drift jumps between runs
# (0.12-0.36 rad/cycle at beta 0.62 for dt 2.5e-5..1e-4 s), so an error there is not a rate.
DRIFT_D31 = (1.9, 2.5, 2.9, 3.5)
DRIFT_REFERENCE: tuple[Integrator, float] = ("rk4", 1e-5)  # converged: docs/NUMERICS.md
TARGET_SPEEDUP = 20.0  # the goal against the paper's RK4 at 2e-5 s (not met: NUMERICS)


def drift_rates(
    integrator: Integrator,
    dt_s: float,
    *,
    params: ModelParams | None = None,
    betas: Sequence[float] = (0.62, 0.70),
    d31s: Sequence[float] = DRIFT_D31,
    duration_s: float = 2.0,
    settle_s: float = 0.5,
    nthread: int = 0,
) -> np.ndarray:
    """Delta31 drift per gait cycle (rad) that the touchdowns would cause, at fixed Delta31.

    With phase resetting off, Delta31 stays where it was put, so every configuration sees the
    same gait; the mean phase jump e_i that leg i's touchdowns would cause (phi_AEP minus the
    phase at touchdown, after `settle_s`) gives the drift 1/4 [(e5 + e6) - (e1 + e2)]: the
    return map's slope field, Delta31_{n+1} - Delta31_n, to first order in the jumps. Unlike a
    final Delta31 after a fixed time, it is well conditioned where the map is nearly neutral:
    there a run's final value integrates every small error, and this measures the error's
    rate. Shape (len(betas), len(d31s)); NaN where a run failed.
    """
    p = params or ModelParams()
    drift, _ = open_loop_drift(p, betas=betas, d31s=d31s, duration_s=duration_s,
                               settle_s=settle_s, integrator=integrator, dt_s=dt_s,
                               control_dt_s=max(p.numerics.control_dt, dt_s),
                               nthread=nthread)  # fmt: skip
    return drift


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
        # within tol the two are one state, even across the gait classifier's boundary
        return [r.difference <= tol for r in self.rows]

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
    *,
    betas: Sequence[float] = (0.62, 0.655, 0.70),
    inits: Sequence[float] = tuple(np.linspace(0, TWO_PI, 8, endpoint=False) + math.pi / 8),
    duration_s: float = 6.0,
    dt_s: float | None = None,
    integrator: Integrator | None = None,
    control_dt_s: float | None = None,
    nthread: int = 0,
    **fields: Any,
) -> ConvergenceReport:
    """Every beta x start run at `dt_s` (None: the model's) and at half of it, the controller
    period held (`control_dt_s`; None: the model's, at least the coarse step); `fields`: the
    other RunSpec fields every run shares (body mass, slope, ...)."""
    p = params or ModelParams()
    dt = dt_s or p.numerics.dt
    integ = integrator or p.numerics.integrator
    control = control_dt_s or max(p.numerics.control_dt, dt)

    def specs(step: float) -> list[RunSpec]:
        return spec_grid(betas, inits, duration_s=duration_s, dt_s=step, control_dt_s=control,
                         integrator=integ, **fields)  # fmt: skip

    coarse = simulate_batch(specs(dt), p, nthread=nthread)
    fine = simulate_batch(specs(dt / 2), p, nthread=nthread)
    rows = []
    for spec, a, b in zip(specs(dt), coarse, fine, strict=True):
        rows.append(
            ConvergenceRow(
                beta=spec.beta,
                d31_init=spec.d31_init,
                final_dt=a.measures.d31_final,
                final_half=b.measures.d31_final,
                gait_dt=a.measures.gait,
                gait_half=b.measures.gait,
            )
        )
    return ConvergenceReport(integ, dt, control, duration_s, rows)


@dataclass(frozen=True)
class GridPoint:
    """One (integrator, dt) configuration measured against the reference."""

    integrator: str
    dt_s: float
    wall_per_sim_s: float  # wall seconds per simulated second, one simulation
    error_rad: float | None  # worst |Delta31 outcome - reference| over the runs; None if failed
    same_gaits: bool
    failure: str | None  # the guard's reason when any run failed
    variant: str = ""  # "" = the defaults; "step touchdown" = no touchdown interpolation
    batch_sim_s_per_wall_s: float | None = None  # BATCH_N simulations on every core
    max_slip: float | None = None  # worst median foot slip per stance, share of the stroke
    finals: tuple[float | None, ...] = ()  # each run's final Delta31, in the grid's run order
    # worst |drift per cycle - the converged reference's| over the probed Delta31 (rad/cycle)
    drift_error: float | None = None
    max_retouches: float | None = None  # worst re-touches per stance (contact chatter)

    @property
    def label(self) -> str:
        return f"{self.integrator} ({self.variant})" if self.variant else self.integrator

    @property
    def status(self) -> str:
        if self.failure is not None:
            return "fails"
        if self.error_rad is not None and self.error_rad <= TOLERANCE_RAD and self.same_gaits:
            return "ok"
        return "inaccurate"


REFERENCE: tuple[Integrator, float] = ("rk4", 2e-5)  # the paper's integrator and step
REFERENCE_CHECK_DT = 1e-5  # the reference is itself checked against RK4 at this step
BATCH_N = 16  # simulations in the throughput measurement (1 s each, every core)
# (label, integrator, parameter overrides): the touchdown-timing variant runs as its own series
STEP_TOUCHDOWN = ("step touchdown", "implicitfast", {"touchdown_interpolation": False})
# The paper's ground (docs/MODEL.md) as its own series, each measured against RK4 at 2e-5 s on
# the same ground: a column of its own, side by side with today's contact in one run
PENALTY_GROUND: tuple[tuple[str, Integrator, dict[str, object]], ...] = (
    ("penalty ground", "implicitfast", {"ground": "penalty"}),
    ("penalty ground", "rk4", {"ground": "penalty"}),
)
# A configuration whose stance feet leave and re-touch the ground this many times per stance
# more than the reference's do chatters: measured 0.0-0.43 on the reference and the default,
# 2.2-2.5 for implicitfast at 5e-4 s (docs/NUMERICS.md)
CHATTER_MARGIN = 1.0


def grid_study(
    *,
    integrators: Sequence[Integrator] = ("euler", "implicit", "implicitfast", "rk4", "discrete"),
    dts: Sequence[float] = (1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2.5e-5, 1e-5),
    betas: Sequence[float] = (0.62, 0.70),
    inits: Sequence[float] = (1.0, 1.8, 2.75),
    duration_s: float = 3.0,
    params: ModelParams | None = None,
    progress: Callable[[str], None] | None = None,
    with_step_touchdown: bool = True,
    with_penalty_ground: bool = True,
    with_batch: bool = True,
    check_reference: bool = True,
    drift_reference: tuple[Integrator, float] | None = DRIFT_REFERENCE,
    drift_d31s: Sequence[float] = DRIFT_D31,
) -> tuple[list[GridPoint], dict[str, object]]:
    """Cost and outcome error of each configuration against RK4 at 2e-5 s (the paper's).

    Outcomes are the final Delta31 of runs from initial values below, on and above the model's
    branch; the comparison is run by run. With drift_reference, each configuration that runs
    also gets its return-map drift error (`drift_rates`) against that configuration's drift.
    Returns the grid and a dict with the reference outcomes and, with check_reference, how far
    RK4 at 1e-5 s is from them.
    """
    import time

    p = params or ModelParams()

    def specs(integ: Integrator, dt: float) -> list[RunSpec]:
        return spec_grid(betas, inits, duration_s=duration_s, integrator=integ, dt_s=dt,
                         control_dt_s=max(p.numerics.control_dt, dt))  # fmt: skip

    t_ref = time.perf_counter()
    ref_runs = simulate_batch(specs(*REFERENCE), p, nthread=1)  # timed like every grid point
    ref = [r.measures.d31_final for r in ref_runs]
    ref_retouch = max(r.measures.retouches_per_stance or 0.0 for r in ref_runs)
    info: dict[str, object] = {
        "reference": ref,
        "reference_config": list(REFERENCE),
        "reference_wall_per_sim_s": (time.perf_counter() - t_ref) / (duration_s * len(ref_runs)),
        "reference_retouches_per_stance": ref_retouch,
    }
    if check_reference:
        finer = simulate_batch(specs(REFERENCE[0], REFERENCE_CHECK_DT), p)
        if any(r.diverged for r in finer):
            info["reference_check"] = "rk4 at 1e-5 s failed"
        else:
            info["reference_check_error_rad"] = worst_error(
                [r.measures.d31_final for r in finer], ref
            )
        if progress is not None:
            got = info.get("reference_check_error_rad", info.get("reference_check"))
            progress(f"reference check (rk4 1e-5 vs 2e-5): {got}")
    ref_drift = None
    if drift_reference is not None:
        ref_drift = drift_rates(*drift_reference, params=p, betas=betas, d31s=drift_d31s)
        info["drift_reference_config"] = list(drift_reference)
        info["drift_reference"] = ref_drift.tolist()
        info["drift_d31s"] = list(drift_d31s)
        if tuple(drift_reference) != REFERENCE:  # the paper's setting against the converged one
            paper = drift_rates(*REFERENCE, params=p, betas=betas, d31s=drift_d31s)
            info["reference_drift_error"] = float(np.max(np.abs(paper - ref_drift)))
        if progress is not None:
            progress(f"drift reference {drift_reference}: {np.round(ref_drift, 4).tolist()}")
    variants: list[tuple[str, Integrator, dict[str, object]]] = [("", i, {}) for i in integrators]
    if with_step_touchdown:
        variants.append(STEP_TOUCHDOWN)  # type: ignore[arg-type]
    if with_penalty_ground:
        variants.extend(PENALTY_GROUND)
    # the reference each variant is measured against: RK4 at 2e-5 s on its own ground
    refs: dict[str, list[float | None]] = {p.contact.ground: ref}
    out: list[GridPoint] = []
    for label, integ, over in variants:
        pv = p.replace(**over) if over else p
        if pv.contact.ground not in refs:
            refs[pv.contact.ground] = [
                r.measures.d31_final for r in simulate_batch(specs(*REFERENCE), pv)
            ]
            info[f"reference_{pv.contact.ground}"] = refs[pv.contact.ground]
        own_ref = refs[pv.contact.ground]
        for dt in dts:
            t0 = time.perf_counter()
            runs = simulate_batch(specs(integ, dt), pv, nthread=1)
            wall = (time.perf_counter() - t0) / (duration_s * len(runs))
            failed = [r.failure for r in runs if r.failure is not None]
            if failed:
                point = GridPoint(integ, dt, wall, None, False, FAILURE_LABEL[failed[0].kind],
                                  label)  # fmt: skip
            else:
                finals = [r.measures.d31_final for r in runs]
                slips = [
                    r.measures.slip_fraction for r in runs if r.measures.slip_fraction is not None
                ]
                thr = None
                if with_batch:
                    bspecs = [RunSpec(beta=betas[k % len(betas)], d31_init=1.0 + 0.1 * k,
                                      duration_s=1.0, integrator=integ, dt_s=dt,
                                      control_dt_s=max(p.numerics.control_dt, dt))
                              for k in range(BATCH_N)]  # fmt: skip
                    t1 = time.perf_counter()
                    simulate_batch(bspecs, pv, nthread=0)
                    thr = BATCH_N / (time.perf_counter() - t1)
                drift_err = None
                if (
                    ref_drift is not None and pv.contact.ground == p.contact.ground
                ):  # drift: today's ground
                    drift = drift_rates(integ, dt, params=pv, betas=betas, d31s=drift_d31s)
                    drift_err = float(np.max(np.abs(drift - ref_drift)))  # NaN if a probe failed
                    drift_err = None if math.isnan(drift_err) else drift_err
                retouch = max(r.measures.retouches_per_stance or 0.0 for r in runs)
                chatter = "contact chatter" if retouch > ref_retouch + CHATTER_MARGIN else None
                betas_run = [r.spec.beta for r in runs]
                point = GridPoint(integ, dt, wall, worst_error(finals, own_ref),
                                  same_gaits(finals, own_ref, betas_run), chatter, label, thr,
                                  max(slips) if slips else None, tuple(finals),
                                  drift_err, retouch)  # fmt: skip
            out.append(point)
            if progress is not None:
                batch = (
                    ""
                    if point.batch_sim_s_per_wall_s is None
                    else (f", batch {point.batch_sim_s_per_wall_s:6.2f} sim s per wall s")
                )
                err = "" if point.error_rad is None else f", error {point.error_rad:.3f} rad"
                if point.drift_error is not None:
                    err += f", drift error {point.drift_error:.4f} rad/cycle"
                if point.failure is not None:
                    err += f" ({point.failure})"
                progress(f"{point.label:30s} dt {dt:8.2g} s: {point.status:10s} "
                         f"{wall:7.3f} wall s per sim s{batch}{err}")  # fmt: skip
    return out, info


def worst_error(finals: Sequence[float | None], against: Sequence[float | None]) -> float:
    """The largest |Delta31 difference| run by run; a run without an outcome counts as pi."""
    return max(
        abs(float(angle_diff(a, b))) if a is not None and b is not None else math.pi
        for a, b in zip(finals, against, strict=True)
    )


def same_gaits(
    finals: Sequence[float | None],
    ref: Sequence[float | None],
    betas: Sequence[float],
    tol: float = TOLERANCE_RAD,
) -> bool:
    """Every run ends in the reference's gait; two outcomes within `tol` of each other count as
    the same gait even when they straddle the classifier's boundary (2.543 vs 2.526 is one
    state, not two gaits)."""
    for f, r, b in zip(finals, ref, betas, strict=True):
        if f is None or r is None:
            return False
        if classify_gait(f, b) != classify_gait(r, b) and abs(float(angle_diff(f, r))) > tol:
            return False
    return True


# the grid's words for each typed failure kind (sim_core.contract.FailureKind)
FAILURE_LABEL: dict[str, str] = {
    "mujoco_error": "MuJoCo error",
    "mujoco_warning": "unstable (MuJoCo warning)",
    "non_finite": "non-finite",
    "flipped": "flip",
    "on_floor": "fall",
    "left_ground": "left the ground",
    "no_footholds": "no footholds",
    "sliding_back": "slid back",
}

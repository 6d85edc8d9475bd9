"""What one simulation run is asked to do (`RunSpec`) and what it gives back (`RunResult`).

The spec carries units in its names because it is the edge that users, the REST service and the
viewer fill in; inside the core everything is SI.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from sim_core.model.params import Integrator, ModelParams, step_problem

TWO_PI = 2.0 * math.pi


class RunSpec(BaseModel):
    """One walking simulation. Validation errors name the field and its allowed range."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    beta: float = Field(0.66, gt=0.5, lt=1.0, description="duty factor (0.5, 1)")
    d31_init: float = Field(
        2.0 * math.pi / 3.0, ge=0.0, le=TWO_PI, description="initial Delta31, rad in [0, 2 pi]"
    )
    duration_s: float = Field(5.0, gt=0.0, le=600.0, description="simulated time, s (0, 600]")
    body_mass_g: float = Field(3.0, gt=0.0, le=30.0, description="body mass, g (0, 30]")
    slope_deg: float = Field(0.0, gt=-90.0, lt=90.0, description="ground slope, deg, uphill +")
    phase_reset: bool = Field(True, description="phase resetting at touchdown (eq. 4)")
    integrator: Integrator | None = Field(None, description="MuJoCo integrator; None = default")
    dt_s: float | None = Field(None, gt=0.0, le=1e-2, description="physics timestep, s")
    control_dt_s: float | None = Field(None, gt=0.0, le=1e-2, description="controller period, s")
    phi1_init: float = Field(0.0, ge=0.0, le=TWO_PI, description="initial phase of leg 1, rad")

    @model_validator(mode="after")
    def _control_not_faster_than_physics(self) -> RunSpec:
        if self.dt_s is not None and self.control_dt_s is not None:
            if self.control_dt_s < self.dt_s * (1 - 1e-9):
                raise ValueError("control_dt_s must be >= dt_s")
        return self


def spec_grid(betas: Iterable[float], d31_inits: Iterable[float], **fields: Any) -> list[RunSpec]:
    """RunSpecs for every beta x initial Delta31 (beta outer, start inner), the other fields
    shared: the grid every protocol of the paper is built from."""
    inits = [float(x) % TWO_PI for x in d31_inits]
    return [RunSpec(beta=b, d31_init=x, **fields) for b in betas for x in inits]


# physics steps per control period beyond which a run could not finish (1e-13 s steps)
MAX_SUBSTEPS = 1e9


def resolve_numerics(
    integrator: str | None,
    dt_s: float | None,
    control_dt_s: float | None,
    params: ModelParams | None = None,
) -> tuple[str, float, float, int]:
    """(integrator, dt, control_dt, substeps per control period) that a run with these
    (possibly null) settings uses: null means the model's default, and the control period is a
    whole number of physics steps, never shorter than one."""
    p = params or ModelParams()
    name = integrator or p.integrator
    dt = dt_s or p.dt
    ratio = (control_dt_s or max(p.control_dt, dt)) / dt
    if not ratio <= MAX_SUBSTEPS:  # also inf, for a step like 5e-324 s
        raise ValueError(
            f"dt_s ({dt:g} s) is too small: one control period would take more than "
            f"{MAX_SUBSTEPS:.0e} physics steps"
        )
    nsub = max(1, round(ratio))
    return name, dt, nsub * dt, nsub


def numerics_problem(
    integrator: str | None, dt_s: float | None, control_dt_s: float | None = None
) -> str | None:
    """Why a run with these (possibly null) numerics cannot be stable, in the words the CLI and
    the REST API both print (`step_problem`, or a step too small to finish); None if it can."""
    try:
        name, dt, _, _ = resolve_numerics(integrator, dt_s, control_dt_s)
    except ValueError as exc:
        return str(exc)
    return step_problem(name, dt, given=dt_s is not None)


# Why a run stopped early. The first three are numerical (a smaller step is the remedy); a flip
# or a fall at a sound step is the insect's physics under those conditions.
FailureKind = Literal["mujoco_error", "mujoco_warning", "non_finite", "flipped", "on_floor"]
FAILURE_KINDS: tuple[FailureKind, ...] = (
    "mujoco_error",
    "mujoco_warning",
    "non_finite",
    "flipped",
    "on_floor",
)
NUMERICAL_FAILURES: frozenset[str] = frozenset({"mujoco_error", "mujoco_warning", "non_finite"})


@dataclass(frozen=True)
class RunFailure:
    """A run that left the physically meaningful region: what, when, and with which numerics."""

    kind: FailureKind
    time_s: float
    integrator: str
    dt_s: float
    reason: str

    @property
    def numerical(self) -> bool:
        """True when the integration blew up (the step is the suspect), False for a fall."""
        return self.kind in NUMERICAL_FAILURES

    def __str__(self) -> str:
        return (
            f"simulation diverged at t = {self.time_s:.4f} s (integrator {self.integrator}, "
            f"dt {self.dt_s:.3g} s): {self.reason}"
        )

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


class SimulationDiverged(RuntimeError):
    """A simulation left the physically meaningful region; it returns no numbers."""

    def __init__(self, failure: RunFailure) -> None:
        self.failure = failure
        super().__init__(str(failure))


@dataclass(frozen=True)
class RunResult:
    """Everything one run recorded. A diverged run has `error` set and empty records."""

    spec: RunSpec
    integrator: str
    dt_s: float
    control_dt_s: float
    # Delta31 = phi3 - phi1 (mod 2 pi) just after each leg-1 touchdown, and when it happened
    d31: np.ndarray
    d31_times_s: np.ndarray
    # records every `record_dt_s`
    times_s: np.ndarray
    stance: np.ndarray  # (T, 6) bool, paper leg order 1..6
    body_pos_m: np.ndarray  # (T, 3), world frame, x along the slope
    body_vel_m_s: np.ndarray  # (T, 3)
    body_quat: np.ndarray  # (T, 4) w, x, y, z
    touchdowns: tuple[np.ndarray, ...]  # per leg: touchdown times (s)
    touchdown_phases: tuple[np.ndarray, ...]  # per leg: phase at touchdown, before resetting
    liftoffs: tuple[np.ndarray, ...]  # per leg: lift-off times (s)
    d31_final: float | None
    gait: str | None
    speed_cm_s: float | None
    duty_factor_measured: float | None
    slip_fraction: float | None  # median foot slip per stance / stroke D
    # median share of the swing done at touchdown (1 = at the AEP), `gait.landing_share`
    landing_swing_share: float | None = None
    # stance feet that rose more than `lift_clearance` and pressed in again, per touchdown:
    # ~0.1-0.4 on the defaults, > 2 where a coarse step makes the contact chatter
    retouches_per_stance: float | None = None
    failure: RunFailure | None = None
    # what the numbers say about themselves (`gait.run_warnings`): a duty factor off beta,
    # feet landing far from the AEP, a step coarser than the converged default
    warnings: tuple[str, ...] = ()

    @property
    def error(self) -> str | None:
        """The failure in words (None for a run that finished)."""
        return None if self.failure is None else str(self.failure)

    @property
    def diverged(self) -> bool:
        return self.failure is not None

    def summary(self) -> dict[str, Any]:
        """The CLI's `--json` object: plain JSON types only."""
        return {
            "beta": self.spec.beta,
            "d31": [float(x) for x in self.d31],
            "d31_final": self.d31_final,
            "gait": self.gait,
            "speed_cm_s": self.speed_cm_s,
            "duty_factor_measured": self.duty_factor_measured,
            "slip_fraction": self.slip_fraction,
            "landing_swing_share": self.landing_swing_share,
            "retouches_per_stance": self.retouches_per_stance,
            "diverged": self.diverged,
            "error": self.error,
            "failure": None if self.failure is None else self.failure.to_dict(),
            "warnings": list(self.warnings),
        }

    def to_dict(self) -> dict[str, Any]:
        """Summary plus the time series, for storage and plotting."""
        out = self.summary()
        out.update(
            {
                "spec": self.spec.model_dump(),
                "integrator": self.integrator,
                "dt_s": self.dt_s,
                "control_dt_s": self.control_dt_s,
                "d31_times_s": self.d31_times_s.tolist(),
                "times_s": self.times_s.tolist(),
                "stance": self.stance.astype(int).tolist(),
                "body_pos_m": self.body_pos_m.tolist(),
                "body_vel_m_s": self.body_vel_m_s.tolist(),
                "body_quat": self.body_quat.tolist(),
                "touchdowns_s": [t.tolist() for t in self.touchdowns],
                "touchdown_phases": [t.tolist() for t in self.touchdown_phases],
                "liftoffs_s": [t.tolist() for t in self.liftoffs],
            }
        )
        return out

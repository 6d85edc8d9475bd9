"""Request and response shapes of the REST API.

Job specs are strict (no coercion from strings, no unknown fields, no NaN) because a job runs
minutes after it was accepted: everything that can be refused must be refused at the door, with
a message naming the field and its allowed range. The physical ranges mirror `sim_core.RunSpec`
(a test keeps them in sync); the API process does not import the core to validate, so that a
request never waits on importing MuJoCo.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    TypeAdapter,
    ValidationInfo,
    field_validator,
)

TWO_PI = 2.0 * math.pi
MAX_LIST = 1000  # hard cap on list lengths; the per-deployment cap is Settings.max_runs_per_job

JobStatus = Literal["queued", "running", "done", "failed", "cancelled"]
JOB_STATUSES: tuple[str, ...] = ("queued", "running", "done", "failed", "cancelled")
FINISHED: frozenset[str] = frozenset({"done", "failed", "cancelled"})
Integrator = Literal["euler", "implicit", "implicitfast", "rk4", "discrete"]


def _num(x: float) -> str:
    if math.isclose(x, TWO_PI):
        return "2*pi (6.283185)"
    return f"{x:g}"


def range_text(
    name: str,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
) -> str:
    """'0.5 < beta < 1': the same bounds the validator enforces, written for people."""
    left = f"{_num(gt)} < " if gt is not None else f"{_num(ge)} <= " if ge is not None else ""
    right = f" < {_num(lt)}" if lt is not None else f" <= {_num(le)}" if le is not None else ""
    return f"{left}{name}{right}"


def bounded(
    default: Any,
    name: str,
    what: str,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    nullable: bool = False,
) -> Any:
    """A numeric field whose bounds and human-readable range come from one set of numbers."""
    allowed = range_text(name, gt=gt, ge=ge, lt=lt, le=le)
    if nullable:
        allowed += " or null (model default)"
    return Field(
        default,
        gt=gt,
        ge=ge,
        lt=lt,
        le=le,
        description=f"{what}; allowed: {allowed}",
        json_schema_extra={"allowed": allowed},
    )


def _integral(v: Any) -> Any:
    """JSON Schema calls 140.0 an integer; accept it as 140, but no strings or 1.5."""
    if isinstance(v, float) and v.is_integer():
        return int(v)
    return v


IntLike = Annotated[int, BeforeValidator(_integral)]
D31 = Annotated[float, Field(ge=0.0, le=TWO_PI)]
D31_ALLOWED = f"1..{MAX_LIST} values, each 0 <= d31_init <= 2*pi (6.283185) rad"


def d31_list(default: list[float]) -> Any:
    return Field(
        default_factory=lambda: list(default),
        min_length=1,
        max_length=MAX_LIST,
        description=f"initial Delta31 values (phi3 - phi1), one simulation each; allowed: "
        f"{D31_ALLOWED}",
        json_schema_extra={"allowed": D31_ALLOWED},
    )


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True)


class _Physics(_Strict):
    """Fields every kind shares; they map one to one onto `sim_core.RunSpec`."""

    body_mass_g: float = bounded(3.0, "body_mass_g", "body mass, g", gt=0.0, le=30.0)
    slope_deg: float = bounded(0.0, "slope_deg", "ground slope, deg, uphill +", gt=-90.0, lt=90.0)
    phase_reset: bool = Field(True, description="phase resetting at touchdown (paper eq. 4)")
    integrator: Integrator | None = Field(
        None,
        description="MuJoCo integrator; allowed: euler, implicit, implicitfast, rk4 or null",
        json_schema_extra={"allowed": "euler, implicit, implicitfast, rk4 or null"},
    )
    dt_s: float | None = bounded(
        None, "dt_s", "physics timestep, s", gt=0.0, le=0.01, nullable=True
    )
    control_dt_s: float | None = bounded(
        None, "control_dt_s", "controller period, s (>= dt_s)", gt=0.0, le=0.01, nullable=True
    )
    duration_s: float = bounded(
        5.0, "duration_s", "simulated time of each run, s", gt=0.0, le=600.0
    )

    @field_validator("control_dt_s")
    @classmethod
    def _control_not_faster_than_physics(cls, v: float | None, info: ValidationInfo) -> Any:
        # a field validator (not a model one) so the 422 names control_dt_s itself
        dt = info.data.get("dt_s")
        if v is not None and dt is not None and v < dt * (1 - 1e-9):
            raise ValueError(f"control_dt_s ({v:g}) must be >= dt_s ({dt:g})")
        return v

    def run_count(self) -> int:
        raise NotImplementedError

    def total_sim_seconds(self) -> float:
        """What the size limit is about: CPU time grows with simulated time, summed over runs."""
        return self.run_count() * self.duration_s

    def run_fields(self) -> dict[str, Any]:
        """The RunSpec keyword arguments shared by every run of this job."""
        return {
            "body_mass_g": self.body_mass_g,
            "slope_deg": self.slope_deg,
            "phase_reset": self.phase_reset,
            "integrator": self.integrator,
            "dt_s": self.dt_s,
            "control_dt_s": self.control_dt_s,
            "duration_s": self.duration_s,
        }


class BetaRange(_Strict):
    """An evenly spaced duty-factor grid; start > stop sweeps downwards (hysteresis runs)."""

    start: float = bounded(..., "start", "first beta", gt=0.5, lt=1.0)
    stop: float = bounded(..., "stop", "last beta", gt=0.5, lt=1.0)
    steps: IntLike = bounded(11, "steps", "grid points, start and stop included", ge=2, le=201)

    def values(self) -> list[float]:
        n = self.steps
        return [self.start + (self.stop - self.start) * i / (n - 1) for i in range(n)]


class RunJob(_Physics):
    """Independent simulations at one beta, one per initial Delta31."""

    kind: Literal["run"] = "run"
    beta: float = bounded(0.66, "beta", "duty factor", gt=0.5, lt=1.0)
    d31_init: list[D31] = d31_list([TWO_PI / 3.0])
    include_series: bool = Field(
        False, description="also keep each run's time series (large); for plots and CSV export"
    )

    def run_count(self) -> int:
        return len(self.d31_init)


class ReturnMapJob(_Physics):
    """Fig. 7 of the paper: pairs (Delta31[n], Delta31[n + lag]) collected over several runs."""

    kind: Literal["return_map"] = "return_map"
    beta: float = bounded(0.66, "beta", "duty factor", gt=0.5, lt=1.0)
    d31_init: list[D31] = d31_list([TWO_PI * i / 12.0 for i in range(12)])
    lag: IntLike = bounded(4, "lag", "touchdowns between the two members of a pair", ge=1, le=50)

    def run_count(self) -> int:
        return len(self.d31_init)


class SweepJob(_Physics):
    """Final gait and Delta31 over a beta grid for each initial Delta31 (paper Figs. 5-6)."""

    kind: Literal["sweep"] = "sweep"
    beta_range: BetaRange
    d31_init: list[D31] = d31_list([TWO_PI / 3.0])

    def run_count(self) -> int:
        return len(self.d31_init) * self.beta_range.steps


class BifurcationJob(_Physics):
    """Delta31 after a transient over a beta grid: the bifurcation diagram (paper Fig. 8)."""

    kind: Literal["bifurcation"] = "bifurcation"
    beta_range: BetaRange
    d31_init: list[D31] = d31_list([TWO_PI * i / 8.0 for i in range(8)])
    transient_s: float = bounded(
        2.0,
        "transient_s",
        "simulated time discarded before Delta31 is recorded, s",
        ge=0.0,
        lt=600.0,
    )

    @field_validator("transient_s")
    @classmethod
    def _transient_shorter_than_run(cls, v: float, info: ValidationInfo) -> float:
        duration = info.data.get("duration_s")
        if duration is not None and v >= duration:
            raise ValueError(f"transient_s ({v:g}) must be < duration_s ({duration:g})")
        return v

    def run_count(self) -> int:
        return len(self.d31_init) * self.beta_range.steps


AnyJob = RunJob | ReturnMapJob | SweepJob | BifurcationJob
JobSpec = Annotated[AnyJob, Field(discriminator="kind")]
JOB_SPEC_ADAPTER: TypeAdapter[AnyJob] = TypeAdapter(JobSpec)
KIND_MODELS: dict[str, type[_Physics]] = {
    "run": RunJob,
    "return_map": ReturnMapJob,
    "sweep": SweepJob,
    "bifurcation": BifurcationJob,
}


# ---- responses --------------------------------------------------------------------------


class JobLinks(BaseModel):
    self: str
    result: str
    figure: str


class Job(BaseModel):
    """A job as clients see it; `error` says why it failed, `note` what happened on the way."""

    id: str
    kind: str
    status: JobStatus
    progress: float = Field(ge=0.0, le=1.0)
    created_at: str
    started_at: str | None
    finished_at: str | None
    error: str | None
    note: str | None
    attempts: int = Field(description="times a worker started this job")
    requeues: int = Field(description="times a server crash interrupted it and it was re-queued")
    sim_seconds: float = Field(description="simulated seconds the job asks for, all runs")
    spec: dict[str, Any]
    links: JobLinks


class JobPage(BaseModel):
    items: list[Job]
    total: int
    limit: int
    offset: int


class ModelParameter(BaseModel):
    name: str
    value: float | int | bool | str | None
    origin: Literal["paper", "invented"]
    reason: str


class WorkerHealth(BaseModel):
    configured: int
    alive: int
    busy: int


class Health(BaseModel):
    status: Literal["ok", "degraded"]
    workers: WorkerHealth
    queued: int
    running: int
    queue_limit: int


class Problem(BaseModel):
    detail: str


class ValidationIssue(BaseModel):
    loc: list[str | int]
    field: str
    msg: str
    type: str
    allowed: str | None = None


class ValidationProblem(BaseModel):
    detail: list[ValidationIssue]

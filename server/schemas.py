"""Request and response shapes of the REST API.

Job specs are strict (no coercion from strings, no unknown fields, no NaN) because a job runs
minutes after it was accepted: everything that can be refused must be refused at the door, with
a message naming the field and its allowed range. The physical ranges mirror `sim_core.RunSpec`
(a test keeps them in sync); the API process does not import the core to validate, so that a
request never waits on importing MuJoCo.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal, get_args

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
INTEGRATOR_NAMES: tuple[str, ...] = get_args(Integrator)  # == sim_core.INTEGRATORS (a test)

# The core's numerics defaults (== sim_core.ModelParams(), a test keeps them equal): the API
# process checks combinations against them without importing MuJoCo.
DEFAULT_INTEGRATOR = "implicitfast"
DEFAULT_DT_S = 5e-5
DEFAULT_CONTROL_DT_S = 5e-4

# The largest timestep at which each integrator keeps this model upright, measured: the
# docs/NUMERICS.md grid (3 s runs, beta 0.62 and 0.70) and 0.5 s runs at beta 0.66 on
# 2026-11-25: euler is unstable (MuJoCo BADQACC) at 2e-5 s, rk4 flips at 2.5e-5 s, implicit and
# implicitfast flip at 1e-3 s in the grid (and within 0.15 s at 2e-3 s), discrete runs at
# 1e-3 s (inaccurately). The explicit integrators need small steps because the insect-scale
# links are tiny and strongly damped.
MAX_STABLE_DT_S: dict[str, float] = {
    "euler": 1e-5,
    "implicit": 5e-4,
    "implicitfast": 5e-4,
    "rk4": 2e-5,
    "discrete": 1e-3,
}
MAX_DT_S = max(MAX_STABLE_DT_S.values())
DT_REASON = (
    "larger steps cannot be stable for this model: measured limits per integrator "
    + ", ".join(f"{k} {v:g} s" for k, v in MAX_STABLE_DT_S.items())
    + f"; null = the default ({DEFAULT_INTEGRATOR} {DEFAULT_DT_S:g} s, converged; see "
    "docs/NUMERICS.md)"
)

# Body mass: the legs are position-servoed and carry any load, so the model "walks" at ~3.0
# cm/s from 1 ug to 30 g (measured 2026-11-25, 1 s runs at beta 0.66): the mass does not stop
# an unphysical insect, the bounds must. Below 0.5 g the body would weigh less than its own
# six legs (6 x 0.11 g = 0.66 g, Table I); above 30 g (ten times the paper's 3 g) the legs'
# gains and contacts were never meant to carry it. The paper's Fig. 9 ramps 1-6 g.
MASS_MIN_G = 0.5
MASS_MAX_G = 30.0
MASS_REASON = (
    "the model's servoed legs carry any load, so lighter or heavier insects would still "
    "'walk'; below 0.5 g the body weighs less than its six legs (0.66 g), above 30 g is ten "
    "times the paper's 3 g"
)


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
    why: str | None = None,
    validate_default: bool = False,
) -> Any:
    """A numeric field whose bounds and human-readable range come from one set of numbers;
    `why` says in the schema why the bounds are where they are."""
    allowed = range_text(name, gt=gt, ge=ge, lt=lt, le=le)
    if nullable:
        allowed += " or null (model default)"
    reason = f" ({why})" if why else ""
    return Field(
        default,
        gt=gt,
        ge=ge,
        lt=lt,
        le=le,
        description=f"{what}; allowed: {allowed}{reason}",
        json_schema_extra={"allowed": allowed},
        validate_default=validate_default,
    )


def tidy(x: float) -> float:
    """x to 12 significant digits: drops binary noise (0.6599999999999999 -> 0.66)."""
    return float(f"{x:.12g}")


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
    """Fields every kind shares; they map one to one onto `sim_core.RunSpec`.

    Cross-field rules run as field validators on the later field (so the 422 names it) with
    `validate_default`, so a default that clashes with a given value is refused too.
    """

    body_mass_g: float = bounded(
        3.0, "body_mass_g", "body mass, g", ge=MASS_MIN_G, le=MASS_MAX_G, why=MASS_REASON
    )
    slope_deg: float = bounded(0.0, "slope_deg", "ground slope, deg, uphill +", gt=-90.0, lt=90.0)
    phase_reset: bool = Field(True, description="phase resetting at touchdown (paper eq. 4)")
    integrator: Integrator | None = Field(
        None,
        description=f"MuJoCo integrator; allowed: {', '.join(INTEGRATOR_NAMES)} or null "
        f"(the default, {DEFAULT_INTEGRATOR})",
        json_schema_extra={"allowed": f"{', '.join(INTEGRATOR_NAMES)} or null"},
    )
    dt_s: float | None = bounded(
        None,
        "dt_s",
        "physics timestep, s",
        gt=0.0,
        le=MAX_DT_S,
        nullable=True,
        why=DT_REASON,
        validate_default=True,
    )
    control_dt_s: float | None = bounded(
        None,
        "control_dt_s",
        "controller period, s (>= dt_s)",
        gt=0.0,
        le=0.01,
        nullable=True,
        validate_default=True,
    )

    @field_validator("dt_s")
    @classmethod
    def _stable_for_the_integrator(cls, v: float | None, info: ValidationInfo) -> Any:
        if "integrator" not in info.data:
            return v  # the integrator itself was refused; that error says enough
        integrator = info.data.get("integrator") or DEFAULT_INTEGRATOR
        dt = DEFAULT_DT_S if v is None else v
        limit = MAX_STABLE_DT_S[integrator]
        if dt > limit * (1 + 1e-9):
            given = f"{dt:g}" if v is not None else f"null, i.e. the default {dt:g}"
            raise ValueError(
                f"dt_s ({given} s) cannot be stable with integrator {integrator}: it needs "
                f"dt_s <= {limit:g} s (measured; see docs/NUMERICS.md)"
            )
        return v

    @field_validator("control_dt_s")
    @classmethod
    def _control_not_faster_than_physics(cls, v: float | None, info: ValidationInfo) -> Any:
        # a field validator (not a model one) so the 422 names control_dt_s itself
        if v is None or "dt_s" not in info.data:
            return v
        given = info.data.get("dt_s")
        dt = DEFAULT_DT_S if given is None else given
        if v < dt * (1 - 1e-9):
            shown = f"{dt:g}" if given is not None else f"the default {dt:g}"
            raise ValueError(f"control_dt_s ({v:g}) must be >= dt_s ({shown})")
        return v

    def effective_control_dt_s(self) -> float:
        dt = self.dt_s or DEFAULT_DT_S
        return self.control_dt_s or max(DEFAULT_CONTROL_DT_S, dt)

    def run_count(self) -> int:
        raise NotImplementedError

    def sim_seconds_per_run(self) -> float:
        raise NotImplementedError

    def total_sim_seconds(self) -> float:
        """What the size limit is about: CPU time grows with simulated time, summed over runs."""
        return self.run_count() * self.sim_seconds_per_run()

    def physics_fields(self) -> dict[str, Any]:
        return {
            "body_mass_g": self.body_mass_g,
            "slope_deg": self.slope_deg,
            "phase_reset": self.phase_reset,
            "integrator": self.integrator,
            "dt_s": self.dt_s,
            "control_dt_s": self.control_dt_s,
        }


class _Timed(_Physics):
    """Kinds whose runs last a fixed `duration_s`."""

    duration_s: float = bounded(
        5.0, "duration_s", "simulated time of each run, s", gt=0.0, le=600.0
    )

    @field_validator("duration_s")
    @classmethod
    def _at_least_one_control_period(cls, v: float, info: ValidationInfo) -> float:
        if "dt_s" in info.data and "control_dt_s" in info.data:
            dt = info.data.get("dt_s") or DEFAULT_DT_S
            period = info.data.get("control_dt_s") or max(DEFAULT_CONTROL_DT_S, dt)
            if v < period:
                raise ValueError(
                    f"duration_s ({v:g}) is shorter than one control period ({period:g} s): "
                    "nothing would be simulated"
                )
        return v

    def sim_seconds_per_run(self) -> float:
        return self.duration_s

    def run_fields(self) -> dict[str, Any]:
        """The RunSpec keyword arguments shared by every run of this job."""
        return {**self.physics_fields(), "duration_s": self.duration_s}


class BetaRange(_Strict):
    """An evenly spaced duty-factor grid; start > stop sweeps downwards (hysteresis runs)."""

    start: float = bounded(..., "start", "first beta", gt=0.5, lt=1.0)
    stop: float = bounded(..., "stop", "last beta", gt=0.5, lt=1.0)
    steps: IntLike = bounded(11, "steps", "grid points, start and stop included", ge=2, le=201)

    def values(self) -> list[float]:
        n = self.steps
        # 12 significant digits: 0.66, not 0.6599999999999999 (grid values are what the
        # client meant, to far below any physical resolution)
        return [tidy(self.start + (self.stop - self.start) * i / (n - 1)) for i in range(n)]


class RunJob(_Timed):
    """Independent simulations at one beta, one per initial Delta31."""

    kind: Literal["run"] = "run"
    beta: float = bounded(0.66, "beta", "duty factor", gt=0.5, lt=1.0)
    d31_init: list[D31] = d31_list([TWO_PI / 3.0])
    include_series: bool = Field(
        False, description="also keep each run's time series (large); for plots and CSV export"
    )

    def run_count(self) -> int:
        return len(self.d31_init)


class ReturnMapJob(_Timed):
    """Fig. 7 of the paper: pairs (Delta31[n], Delta31[n + lag]) collected over several runs."""

    kind: Literal["return_map"] = "return_map"
    beta: float = bounded(0.66, "beta", "duty factor", gt=0.5, lt=1.0)
    d31_init: list[D31] = d31_list([TWO_PI * i / 12.0 for i in range(12)])
    lag: IntLike = bounded(4, "lag", "touchdowns between the two members of a pair", ge=1, le=50)

    def run_count(self) -> int:
        return len(self.d31_init)


class SweepJob(_Timed):
    """Final gait and Delta31 over a beta grid for each initial Delta31 (paper Figs. 5-6)."""

    kind: Literal["sweep"] = "sweep"
    beta_range: BetaRange
    d31_init: list[D31] = d31_list([TWO_PI / 3.0])

    def run_count(self) -> int:
        return len(self.d31_init) * self.beta_range.steps


class BifurcationJob(_Timed):
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
        validate_default=True,
    )

    @field_validator("transient_s")
    @classmethod
    def _transient_shorter_than_run(cls, v: float, info: ValidationInfo) -> float:
        duration = info.data.get("duration_s")
        if duration is not None and v >= duration:
            raise ValueError(
                f"transient_s ({v:g} s) must be < duration_s ({duration:g} s); transient_s is "
                "2 s when not given"
            )
        return v

    def run_count(self) -> int:
        return len(self.d31_init) * self.beta_range.steps


SweptParameter = Literal["beta", "body_mass_g", "slope_deg"]
# the range each swept parameter may take: the same bounds as the field of that name
SWEEP_RANGES: dict[str, dict[str, float]] = {
    "beta": {"gt": 0.5, "lt": 1.0},
    "body_mass_g": {"ge": MASS_MIN_G, "le": MASS_MAX_G},
    "slope_deg": {"gt": -90.0, "lt": 90.0},
}
MAX_SWEEP_S = 600.0


def _in_range(value: float, bounds: dict[str, float]) -> bool:
    return (
        value > bounds.get("gt", -math.inf)
        and value >= bounds.get("ge", -math.inf)
        and value < bounds.get("lt", math.inf)
        and value <= bounds.get("le", math.inf)
    )


class HysteresisJob(_Physics):
    """The paper's Figs. 6a and 9 protocol in one run: hold `parameter` at `start` for
    `hold_s`, ramp it to `turn` in `ramp_s`, back to `start` in `ramp_s`, hold again, and record
    Delta31 at every leg-1 touchdown against the value it had then (`sim_core.sweep`)."""

    kind: Literal["hysteresis"] = "hysteresis"
    parameter: SweptParameter = Field(
        "beta",
        description="the RunSpec field that is ramped: beta, body_mass_g or slope_deg; "
        "its start value is `start` (which wins over a field of the same name)",
        json_schema_extra={"allowed": "beta, body_mass_g, slope_deg"},
    )
    beta: float = bounded(
        0.66, "beta", "duty factor held while another parameter is swept", gt=0.5, lt=1.0
    )
    d31_init: D31 = Field(
        1.9,
        description="initial Delta31, rad (default 1.9: the metachronal branch, where the "
        "paper's sweeps start); allowed: 0 <= d31_init <= 2*pi (6.283185)",
        json_schema_extra={"allowed": "0 <= d31_init <= 2*pi (6.283185)"},
    )
    start: float = Field(
        ...,
        allow_inf_nan=False,
        description="value held first and last (Fig. 6a: beta 0.70); allowed: the range of "
        "the swept field (beta 0.5 < x < 1, body_mass_g 0.5 <= x <= 30, slope_deg "
        "-90 < x < 90)",
    )
    turn: float = Field(
        ...,
        allow_inf_nan=False,
        description="value the ramp turns at (Fig. 6a: beta 0.62); same range as start, != start",
    )
    hold_s: float = bounded(5.0, "hold_s", "seconds held at start, before and after", gt=0.0,
                            le=60.0)  # fmt: skip
    ramp_s: float = bounded(
        30.0, "ramp_s", "seconds for each leg of the ramp (start -> turn, turn -> start)",
        gt=0.0, le=280.0, validate_default=True,
    )  # fmt: skip

    @field_validator("start", "turn")
    @classmethod
    def _within_the_parameter_range(cls, v: float, info: ValidationInfo) -> float:
        param = info.data.get("parameter")
        if param is None:
            return v
        bounds = SWEEP_RANGES[param]
        if not _in_range(v, bounds):
            raise ValueError(
                f"{info.field_name} ({v:g}) is outside the range of {param}: "
                f"{range_text(param, **bounds)}"
            )
        if info.field_name == "turn" and "start" in info.data and v == info.data["start"]:
            raise ValueError(f"turn ({v:g}) must differ from start: nothing would be swept")
        return v

    @field_validator("ramp_s")
    @classmethod
    def _schedule_fits_one_run(cls, v: float, info: ValidationInfo) -> float:
        hold = info.data.get("hold_s")
        if hold is not None and 2 * hold + 2 * v > MAX_SWEEP_S:
            raise ValueError(
                f"the sweep lasts 2 x hold_s + 2 x ramp_s = {2 * hold + 2 * v:g} s; at most "
                f"{MAX_SWEEP_S:g} s (one run's limit)"
            )
        return v

    def run_count(self) -> int:
        return 1

    def sim_seconds_per_run(self) -> float:
        return 2.0 * self.hold_s + 2.0 * self.ramp_s

    def run_fields(self) -> dict[str, Any]:
        """The RunSpec of the sweep's start (its duration is set by the schedule)."""
        out = {**self.physics_fields(), "beta": self.beta, "d31_init": self.d31_init}
        out[self.parameter] = self.start
        out["duration_s"] = self.sim_seconds_per_run()
        return out


AnyJob = RunJob | ReturnMapJob | SweepJob | BifurcationJob | HysteresisJob
JobSpec = Annotated[AnyJob, Field(discriminator="kind")]
JOB_SPEC_ADAPTER: TypeAdapter[AnyJob] = TypeAdapter(JobSpec)
KIND_MODELS: dict[str, type[_Physics]] = {
    "run": RunJob,
    "return_map": ReturnMapJob,
    "sweep": SweepJob,
    "bifurcation": BifurcationJob,
    "hysteresis": HysteresisJob,
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
    eta_s: float | None = Field(
        None,
        description="running jobs: estimated seconds left, from the job's own progress rate "
        "(or, before it reports progress, from recent jobs' wall time per simulated second); "
        "null otherwise",
    )
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


class IntegratorInfo(BaseModel):
    name: str
    default: bool = Field(description="the integrator used when a job gives null")
    default_dt_s: float | None = Field(description="its timestep when dt_s is null")
    max_stable_dt_s: float = Field(
        description="largest dt_s accepted with it: larger steps were measured unstable "
        "(docs/NUMERICS.md)"
    )


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

"""Request and response shapes of the REST API.

Job specs are strict (no coercion from strings, no unknown fields, no NaN) because a job runs
minutes after it was accepted: everything that can be refused must be refused at the door, with
a message naming the field and its allowed range. The rules are the core's own
(`sim_core.contract`: RunSpec's ranges and defaults, the integrators with their measured step
limits, the run's numerics): this module composes them and states only tighter bounds, each
with its reason. The contract loads without MuJoCo, so validating a request never waits on the
physics engine.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

import annotated_types
from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    TypeAdapter,
    ValidationInfo,
    field_validator,
)

from sim_core.contract import (
    AXIS_PARAM,
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    INTEGRATORS,
    MASS_REASON,
    MAX_STABLE_DT_S,
    MIN_DT_S,
    AtlasAxis,
    FinderConfig,
    Integrator,
    RampParam,
    RunSpec,
    cost_problem,
    numerics_problem,
    resolve_numerics,
)

TWO_PI = 2.0 * math.pi
MAX_LIST = 1000  # hard cap on list lengths; the per-deployment cap is Settings.max_runs_per_job

JobStatus = Literal["queued", "running", "done", "failed", "cancelled"]
JOB_STATUSES: tuple[str, ...] = ("queued", "running", "done", "failed", "cancelled")
FINISHED: frozenset[str] = frozenset({"done", "failed", "cancelled"})


def core_bounds(name: str) -> dict[str, float]:
    """RunSpec's bounds on field `name` as keyword arguments (gt/ge/lt/le): the API's ranges
    are the core's, read from it, never retyped."""
    out: dict[str, float] = {}
    for m in RunSpec.model_fields[name].metadata:
        for key, kind in (("gt", annotated_types.Gt), ("ge", annotated_types.Ge),
                          ("lt", annotated_types.Lt), ("le", annotated_types.Le)):  # fmt: skip
            if isinstance(m, kind):
                out[key] = float(getattr(m, key))
    return out


def core_default(name: str) -> Any:
    return RunSpec.model_fields[name].default


MAX_DT_S = max(MAX_STABLE_DT_S.values())
DT_REASON = (
    "larger steps cannot be stable for this model: measured limits per integrator "
    + ", ".join(f"{k} {v:g} s" for k, v in MAX_STABLE_DT_S.items())
    + f"; steps below {MIN_DT_S:g} s are refused as too costly (a tenth of the finest step "
    f"the model needed); null = the default ({DEFAULT_INTEGRATOR} {DEFAULT_DT_S:g} s, "
    "converged; see docs/NUMERICS.md)"
)

# Body mass: the core's bounds and reason (`sim_core.contract.MASS_MIN_G`, `MASS_REASON`)
MASS_BOUNDS = core_bounds("body_mass_g")
BETA_BOUNDS = core_bounds("beta")
BETA_DEFAULT: float = core_default("beta")
SLOPE_BOUNDS = core_bounds("slope_deg")
DURATION_BOUNDS = core_bounds("duration_s")
D31_BOUNDS = core_bounds("d31_init")


def step_weight(spec: dict[str, Any]) -> float:
    """Physics steps per simulated second of a job spec (its integrator, dt_s, control_dt_s,
    possibly null or absent) against the default step's: 1 at the default, 10 at 5e-6 s. The
    job-size limit and the time estimates (`server.estimates`) scale with it."""
    dt = resolve_numerics(spec.get("integrator"), spec.get("dt_s"), spec.get("control_dt_s"))[1]
    return DEFAULT_DT_S / dt


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
D31 = Annotated[float, Field(**D31_BOUNDS)]
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
        core_default("body_mass_g"), "body_mass_g", "body mass, g", **MASS_BOUNDS, why=MASS_REASON
    )
    slope_deg: float = bounded(
        core_default("slope_deg"), "slope_deg", "ground slope, deg, uphill +", **SLOPE_BOUNDS
    )
    phase_reset: bool = Field(
        core_default("phase_reset"), description="phase resetting at touchdown (paper eq. 4)"
    )
    integrator: Integrator | None = Field(
        None,
        description=f"MuJoCo integrator; allowed: {', '.join(INTEGRATORS)} or null "
        f"(the default, {DEFAULT_INTEGRATOR})",
        json_schema_extra={"allowed": f"{', '.join(INTEGRATORS)} or null"},
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
        problem = numerics_problem(info.data.get("integrator"), v)
        if problem:
            raise ValueError(problem)
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
        return resolve_numerics(self.integrator, self.dt_s, self.control_dt_s)[2]

    def effective_dt_s(self) -> float:
        return resolve_numerics(self.integrator, self.dt_s, self.control_dt_s)[1]

    def keeps_series(self) -> bool:
        return False

    def cost_problem(self) -> str | None:
        """The core's cost rule for the whole job (`sim_core.contract.cost_problem`): steps per
        run and the memory of all its runs at once; None if it fits."""
        return cost_problem(
            self.sim_seconds_per_run(), self.integrator, self.dt_s, self.control_dt_s,
            runs=self.run_count(), series=self.keeps_series(),
        )  # fmt: skip

    def run_count(self) -> int:
        raise NotImplementedError

    def sim_seconds_per_run(self) -> float:
        raise NotImplementedError

    def total_sim_seconds(self) -> float:
        """Simulated seconds, summed over runs."""
        return self.run_count() * self.sim_seconds_per_run()

    def step_weight(self) -> float:
        """Physics steps per simulated second against the default step's (dt_s 5e-6 s: 10):
        CPU time grows with the steps, not with simulated time alone."""
        return step_weight(self.spec_numerics())

    def spec_numerics(self) -> dict[str, Any]:
        return {"integrator": self.integrator, "dt_s": self.dt_s, "control_dt_s": self.control_dt_s}

    def size_sim_seconds(self) -> float:
        """What the job-size limit (max_job_sim_seconds) counts: simulated seconds summed over
        runs, a finer step than the default counted as that many more (a coarser one as 1)."""
        return self.total_sim_seconds() * max(1.0, self.step_weight())

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
        core_default("duration_s"),
        "duration_s",
        "simulated time of each run, s",
        **DURATION_BOUNDS,
    )

    @field_validator("duration_s")
    @classmethod
    def _at_least_one_control_period(cls, v: float, info: ValidationInfo) -> float:
        if "dt_s" in info.data and "control_dt_s" in info.data:
            period = resolve_numerics(
                info.data.get("integrator"), info.data.get("dt_s"), info.data.get("control_dt_s")
            )[2]
            if v < period:
                raise ValueError(
                    f"duration_s ({v:g}) is shorter than one control period ({period:g} s): "
                    "nothing would be simulated"
                )
            problem = _run_cost_problem(v, info)
            if problem:
                raise ValueError(problem)
        return v

    def sim_seconds_per_run(self) -> float:
        return self.duration_s

    def run_fields(self) -> dict[str, Any]:
        """The RunSpec keyword arguments shared by every run of this job."""
        return {**self.physics_fields(), "duration_s": self.duration_s}


def _run_cost_problem(duration_s: float, info: ValidationInfo) -> str | None:
    """The core's per-run cost rule (the CLI's too) once the numerics fields are valid."""
    if not {"integrator", "dt_s", "control_dt_s"} <= set(info.data):
        return None  # a numerics field was refused; that error says enough
    d = info.data
    return cost_problem(duration_s, d["integrator"], d["dt_s"], d["control_dt_s"])


class BetaRange(_Strict):
    """An evenly spaced duty-factor grid; start > stop sweeps downwards (hysteresis runs)."""

    start: float = bounded(..., "start", "first beta", **BETA_BOUNDS)
    stop: float = bounded(..., "stop", "last beta", **BETA_BOUNDS)
    steps: IntLike = bounded(11, "steps", "grid points, start and stop included", ge=2, le=201)

    @field_validator("stop")
    @classmethod
    def _a_range_not_a_point(cls, v: float, info: ValidationInfo) -> float:
        # refused, not run once: `steps` points of one beta would be identical simulations,
        # and a client who sent start == stop most likely mistyped one of them
        if info.data.get("start") == v:
            raise ValueError(
                f"stop ({v:g}) equals start: every grid point would be the same beta and the "
                "runs identical; for one beta send a 'run' job, else make stop differ from start"
            )
        return v

    def values(self) -> list[float]:
        n = self.steps
        # 12 significant digits: 0.66, not 0.6599999999999999 (grid values are what the
        # client meant, to far below any physical resolution)
        return [tidy(self.start + (self.stop - self.start) * i / (n - 1)) for i in range(n)]


class RunJob(_Timed):
    """Independent simulations at one beta, one per initial Delta31."""

    kind: Literal["run"] = "run"
    beta: float = bounded(BETA_DEFAULT, "beta", "duty factor", **BETA_BOUNDS)
    d31_init: list[D31] = d31_list([core_default("d31_init")])
    include_series: bool = Field(
        False, description="also keep each run's time series (large); for plots and CSV export"
    )

    def run_count(self) -> int:
        return len(self.d31_init)

    def keeps_series(self) -> bool:
        return self.include_series


class ReturnMapJob(_Timed):
    """Fig. 7 of the paper: pairs (Delta31[n], Delta31[n + lag]) collected over several runs."""

    kind: Literal["return_map"] = "return_map"
    beta: float = bounded(BETA_DEFAULT, "beta", "duty factor", **BETA_BOUNDS)
    d31_init: list[D31] = d31_list([TWO_PI * i / 12.0 for i in range(12)])
    lag: IntLike = bounded(4, "lag", "touchdowns between the two members of a pair", ge=1, le=50)

    def run_count(self) -> int:
        return len(self.d31_init)


class SweepJob(_Timed):
    """Final gait and Delta31 over a beta grid for each initial Delta31 (paper Figs. 5-6)."""

    kind: Literal["sweep"] = "sweep"
    beta_range: BetaRange
    d31_init: list[D31] = d31_list([core_default("d31_init")])

    def run_count(self) -> int:
        return len(self.d31_init) * self.beta_range.steps


_FINDER = FinderConfig()


class _Finder(_Physics):
    """Kinds answered by the settled fixed-point finder (`sim_core.contract.find`): settled
    runs from starts spread over the circle, judged by the core's one settled rule."""

    starts: IntLike = bounded(
        _FINDER.starts, "starts", "starts spread over the circle per beta", ge=2, le=16
    )
    duration_s: float = bounded(
        _FINDER.duration_s, "duration_s",
        "simulated time of each start's run, s (the settled rule needs a last quarter of "
        "40 gait cycles, ~16-20 s; near a fold 40 s tells a ghost from a gait)",
        ge=2.0, le=DURATION_BOUNDS["le"],
    )  # fmt: skip

    def run_count(self) -> int:
        return self.cells() * (self.starts + self.extra_runs_per_cell())

    def sim_seconds_per_run(self) -> float:
        return self.duration_s

    def total_sim_seconds(self) -> float:
        return self.cells() * (self.starts * self.duration_s + self.extra_sim_seconds_per_cell())

    def cells(self) -> int:
        raise NotImplementedError

    def extra_runs_per_cell(self) -> int:
        return 0

    def extra_sim_seconds_per_cell(self) -> float:
        return 0.0

    def numerics_fields(self) -> dict[str, Any]:
        """RunSpec fields besides beta, mass, slope (those come from the finder's cells)."""
        out = self.physics_fields()
        del out["body_mass_g"], out["slope_deg"]
        return out


class BifurcationJob(_Finder):
    """The paper's Fig. 8 over a beta grid, from settled walking (the fixed-point finder, the
    same function as `insect-gait reproduce`): stable gaits with how many starts reach them
    and their map slope, unstable ones as bisected basin borders, ghosts, and the runs that
    did not settle in the time given."""

    kind: Literal["bifurcation"] = "bifurcation"
    beta_range: BetaRange
    bisect_duration_s: float = bounded(
        _FINDER.bisect_duration_s, "bisect_duration_s",
        "simulated time of a bisection run, s (re-run at duration_s if it has not settled)",
        ge=2.0, le=DURATION_BOUNDS["le"],
    )  # fmt: skip
    border_tol_rad: float = bounded(
        _FINDER.border_tol_rad, "border_tol_rad", "width of a bisected border's bracket, rad",
        ge=0.005, le=1.0,
    )  # fmt: skip
    max_borders: IntLike = bounded(
        _FINDER.max_borders, "max_borders", "basin borders bisected per beta", ge=0, le=4
    )

    def cells(self) -> int:
        return self.beta_range.steps

    def bisect_steps(self) -> int:
        """Bisection runs one border may take: from the starts' spacing to border_tol_rad."""
        return max(1, math.ceil(math.log2(2 * math.pi / self.starts / self.border_tol_rad)))

    def extra_runs_per_cell(self) -> int:
        return self.max_borders * self.bisect_steps()

    def extra_sim_seconds_per_cell(self) -> float:
        return self.extra_runs_per_cell() * self.bisect_duration_s

    def finder_config(self) -> FinderConfig:
        return FinderConfig(
            starts=self.starts, duration_s=self.duration_s,
            bisect_duration_s=self.bisect_duration_s, border_tol_rad=self.border_tol_rad,
            max_borders=self.max_borders,
        )  # fmt: skip


class AtlasJob(_Finder):
    """The gait atlas on a small grid: which gaits are stable over beta x body mass or beta x
    slope (the same function as `insect-gait atlas`), each cell seeded with its neighbours'
    attractors; no bisection."""

    kind: Literal["atlas"] = "atlas"
    axis: AtlasAxis = Field(
        "mass", description="the second axis: mass (body_mass_g) or slope (slope_deg)",
        json_schema_extra={"allowed": "mass, slope"},
    )  # fmt: skip
    betas: list[Annotated[float, Field(gt=0.5, lt=1.0, allow_inf_nan=False)]] = Field(
        [0.62, 0.70], min_length=1, max_length=8,
        description="duty factors of the grid (1-8 values)",
    )  # fmt: skip
    values: list[Annotated[float, Field(allow_inf_nan=False)]] = Field(
        [2.0, 5.0], min_length=1, max_length=8,
        description="values of the axis (g for mass, deg for slope; 1-8 values)",
    )  # fmt: skip
    starts: IntLike = bounded(4, "starts", "starts spread over the circle per cell", ge=2, le=16)
    duration_s: float = bounded(
        30.0, "duration_s", "simulated time of each run, s", ge=2.0, le=DURATION_BOUNDS["le"]
    )

    @field_validator("values")
    @classmethod
    def _in_the_axis_range(cls, v: list[float], info: ValidationInfo) -> list[float]:
        axis = info.data.get("axis")
        if axis is None:
            return v
        param = AXIS_PARAM[axis]
        bounds = SWEEP_RANGES[param]
        for x in v:
            if not _in_range(x, bounds):
                raise ValueError(f"{x:g} is outside the range of {param}: "
                                 f"{range_text(param, **bounds)}")  # fmt: skip
        return v

    def cells(self) -> int:
        return len(self.betas) * len(self.values)

    def extra_runs_per_cell(self) -> int:
        return 3  # seeds: at most the attractors of three neighbours, one per place (~1-3)

    def extra_sim_seconds_per_cell(self) -> float:
        return self.extra_runs_per_cell() * self.duration_s


SweptParameter = RampParam
# the range each swept parameter may take: the same bounds as the field of that name
SWEEP_RANGES: dict[str, dict[str, float]] = {
    "beta": BETA_BOUNDS,
    "body_mass_g": MASS_BOUNDS,
    "slope_deg": SLOPE_BOUNDS,
}
MAX_SWEEP_S = DURATION_BOUNDS["le"]


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
        BETA_DEFAULT,
        "beta",
        "duty factor held while another parameter is swept",
        **BETA_BOUNDS,
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
        "the swept field ("
        + ", ".join(f"{k} {range_text('x', **b)}" for k, b in SWEEP_RANGES.items())
        + ")",
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
        if hold is not None:
            problem = _run_cost_problem(2 * hold + 2 * v, info)
            if problem:
                raise ValueError(problem)
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


AnyJob = RunJob | ReturnMapJob | SweepJob | BifurcationJob | HysteresisJob | AtlasJob
JobSpec = Annotated[AnyJob, Field(discriminator="kind")]
JOB_SPEC_ADAPTER: TypeAdapter[AnyJob] = TypeAdapter(JobSpec)
KIND_MODELS: dict[str, type[_Physics]] = {
    "run": RunJob,
    "return_map": ReturnMapJob,
    "sweep": SweepJob,
    "bifurcation": BifurcationJob,
    "hysteresis": HysteresisJob,
    "atlas": AtlasJob,
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

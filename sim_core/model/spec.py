"""What one simulation run is asked to do (`RunSpec`) and what it gives back (`RunResult`).

The spec carries units in its names because it is the edge that users, the REST service and the
viewer fill in; inside the core everything is SI.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import asdict, dataclass, fields
from typing import Any, Literal, get_args

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from sim_core.model.cost import MAX_JOB_BYTES, MAX_STEPS_PER_RUN, MIN_DT_S, gib, run_cost
from sim_core.model.gait import TWO_PI
from sim_core.model.params import Integrator, ModelParams, step_problem

# Body mass: the legs are position-servoed and carry any load, so the model "walks" at ~3.0
# cm/s from 1 ug to 30 g (measured in 1 s runs at beta 0.66): the mass does not stop
# an unphysical insect, the bounds must. Below 0.5 g the body would weigh less than its own
# six legs (6 x 0.11 g = 0.66 g, Table I); the top is ten times the paper's 3 g. The paper's
# Fig. 9 ramps 1-6 g. The CLI and the REST API refuse with this range and this reason.
MASS_MIN_G = 0.5
MASS_MAX_G = 30.0
MASS_REASON = (
    "the model's servoed legs carry any load, so lighter or heavier insects would still "
    f"'walk'; below {MASS_MIN_G:g} g the body weighs less than its six legs (0.66 g), above "
    f"{MASS_MAX_G:g} g is ten times the paper's 3 g"
)


# The drift surface's pin (docs/MODEL.md, "Instruments"): K = 30 per s settles the pinned walk
# in about a gait cycle (K T ~ 3) and agrees with K = 10 within 0.3 mrad per cycle; K >= 100
# biases the drift by 1-2 mrad (shared/notes/drift-surface.md; remeasured: docs/studies/journal.md).
PIN_GAIN_PER_S = 30.0
PIN_GAIN_MAX_PER_S = 1000.0
PIN_GAIN_REASON = (
    "a stiff pin undoes the resets' own within-cycle motion and biases the drift it measures; "
    "10-30 per s is the measured range"
)


def pin_problem(pin_d31: float | None, phase_reset: bool) -> str | None:
    """Why a pin makes no sense with these settings, in the words the CLI and the REST API
    both print; None if it does (or no pin is asked for)."""
    if pin_d31 is None:
        return None
    if not phase_reset:
        return (
            "pin_d31 needs phase resetting (eq. 4) on: the pin measures the drift the resets "
            "cause at a held Delta31, and without resets Delta31 does not drift at all"
        )
    if not 0.0 <= pin_d31 < TWO_PI:
        return f"pin_d31 ({pin_d31:g}) must be an angle in [0, 2 pi), rad"
    return None


class RunSpec(BaseModel):
    """One walking simulation. Validation errors name the field and its allowed range."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    beta: float = Field(0.66, gt=0.5, lt=1.0, description="duty factor (0.5, 1)")
    d31_init: float = Field(
        TWO_PI / 3.0, ge=0.0, le=TWO_PI, description="initial Delta31, rad in [0, 2 pi]"
    )
    duration_s: float = Field(5.0, gt=0.0, le=600.0, description="simulated time, s (0, 600]")
    body_mass_g: float = Field(
        3.0,
        ge=MASS_MIN_G,
        le=MASS_MAX_G,
        description=f"body mass, g [{MASS_MIN_G:g}, {MASS_MAX_G:g}]: {MASS_REASON}",
    )
    slope_deg: float = Field(0.0, gt=-90.0, lt=90.0, description="ground slope, deg, uphill +")
    phase_reset: bool = Field(True, description="phase resetting at touchdown (eq. 4)")
    integrator: Integrator | None = Field(None, description="MuJoCo integrator; null: the model's")
    dt_s: float | None = Field(None, gt=0.0, le=1e-2, description="physics timestep, s")
    control_dt_s: float | None = Field(
        None, gt=0.0, le=1e-2, description="controller period, s (>= dt_s)"
    )
    phi1_init: float = Field(
        0.0, ge=0.0, le=TWO_PI, description="initial phase of leg 1, rad in [0, 2 pi]"
    )
    stop_if_settled_s: float | None = Field(
        None,
        gt=0.0,
        description="at this simulated time, s, a run whose Delta31 has settled (the settled "
        "rule, gait.settling) stops; one that has not runs on to duration_s. The run up to "
        "then is the same as a run of that length, so one spec does a short try and its "
        "longer re-run without simulating the start twice",
    )

    pin_d31: float | None = Field(
        None,
        ge=0.0,
        lt=TWO_PI,
        description="a measuring device, not the paper's model: hold Delta31 = Delta53 near "
        "this value, rad in [0, 2 pi), by a weak pin on the fore and hind oscillators (the "
        "drift surface, sim_core.paper.surface)",
    )
    pin_gain_per_s: float = Field(
        PIN_GAIN_PER_S,
        gt=0.0,
        le=PIN_GAIN_MAX_PER_S,
        description=f"the pin's gain K, 1/s (0, {PIN_GAIN_MAX_PER_S:g}]: {PIN_GAIN_REASON}",
    )

    @model_validator(mode="after")
    def _control_not_faster_than_physics(self) -> RunSpec:
        problem = pin_problem(self.pin_d31, self.phase_reset)
        if problem:
            raise ValueError(problem)
        problem = control_problem(self.dt_s, self.control_dt_s)
        if problem:
            raise ValueError(problem)
        if self.stop_if_settled_s is not None and self.stop_if_settled_s > self.duration_s:
            raise ValueError("stop_if_settled_s must be <= duration_s")
        return self


def control_problem(dt_s: float | None, control_dt_s: float | None) -> str | None:
    """Why a controller period shorter than the physics step is refused (a null step is the
    model's), in the words RunSpec, the CLI and the REST API share; None if it is not."""
    if control_dt_s is None:
        return None
    dt = ModelParams().numerics.dt if dt_s is None else dt_s
    if control_dt_s < dt * (1 - 1e-9):
        shown = f"{dt:g}" if dt_s is not None else f"the default {dt:g}"
        return f"control_dt_s ({control_dt_s:g}) must be >= dt_s ({shown})"
    return None


def check_field(name: str, value: float) -> None:
    """A value changed mid-run (a ramp, the viewer's sliders) checked against RunSpec's own
    bounds for that field, so every range is written once; ValueError with pydantic's words."""
    try:
        RunSpec.model_validate({name: value})
    except ValidationError as e:
        raise ValueError(f"{name} = {value:g}: {e.errors()[0]['msg']}") from None


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
    name = integrator or p.numerics.integrator
    dt = dt_s or p.numerics.dt
    ratio = (control_dt_s or max(p.numerics.control_dt, dt)) / dt
    if not ratio <= MAX_SUBSTEPS:  # also inf, for a step like 5e-324 s
        raise ValueError(
            f"dt_s ({dt:g} s) is too small: one control period would take more than "
            f"{MAX_SUBSTEPS:.0e} physics steps"
        )
    nsub = max(1, round(ratio))
    return name, dt, nsub * dt, nsub


def step_too_fine(dt_s: float | None) -> str | None:
    """Why a step below `MIN_DT_S` is refused (None for null or a step at or above it)."""
    if dt_s is not None and not dt_s >= MIN_DT_S:
        return (
            f"dt_s ({dt_s:g} s) is too small: the smallest step a run may take is {MIN_DT_S:g} s, "
            "a tenth of the finest step the model needed (RK4 at 1e-05 s is its converged "
            "reference, docs/NUMERICS.md); a finer step buys no accuracy, only time and memory"
        )
    return None


def numerics_problem(
    integrator: str | None, dt_s: float | None, control_dt_s: float | None = None
) -> str | None:
    """Why a run with these (possibly null) numerics cannot be stable, in the words the CLI and
    the REST API both print (`step_problem`, or a step below `MIN_DT_S`); None if it can."""
    too_fine = step_too_fine(dt_s)
    if too_fine:
        return too_fine
    try:
        name, dt, _, _ = resolve_numerics(integrator, dt_s, control_dt_s)
    except ValueError as exc:
        return str(exc)
    return step_problem(name, dt, given=dt_s is not None)


def cost_problem(
    duration_s: float,
    integrator: str | None,
    dt_s: float | None,
    control_dt_s: float | None,
    *,
    runs: int = 1,
    series: bool = False,
) -> str | None:
    """Why runs of `duration_s` at these (possibly null) numerics cost more than one run or one
    job may (`MAX_STEPS_PER_RUN`, `MAX_JOB_BYTES`), in the words the CLI and the REST API both
    print; None if they fit. `runs` runs held at once (a job), `series` kept as lists."""
    too_fine = step_too_fine(dt_s)
    if too_fine:
        return too_fine
    try:
        _, dt, control_dt, _ = resolve_numerics(integrator, dt_s, control_dt_s)
    except ValueError as exc:
        return str(exc)
    cost = run_cost(duration_s, dt, control_dt, series=series)
    if cost.steps > MAX_STEPS_PER_RUN:
        return (
            f"duration_s {duration_s:g} s at dt_s {dt:g} s is {cost.steps:.2g} physics steps; a "
            f"run may take at most {MAX_STEPS_PER_RUN:.0e} (600 s at 1e-05 s, about 25 min of "
            "one core): shorten duration_s or take a larger dt_s"
        )
    total = runs * cost.bytes
    if total > MAX_JOB_BYTES:
        what = f"{runs} runs of {duration_s:g} s" if runs > 1 else f"a run of {duration_s:g} s"
        kept = " with their time series (include_series)" if series else ""
        return (
            f"{what}{kept} would hold about {gib(total)} of memory; a job may hold at most "
            f"{gib(MAX_JOB_BYTES)}: run fewer or shorter runs per job"
            + (", or leave out include_series" if series else "")
        )
    return None


# Why a run stopped early. The first three are numerical (a smaller step is the remedy); the
# others are the insect's physics under those conditions: it flipped, fell on its belly, or
# could no longer walk (left the ground, lost every foothold, slid backwards).
FailureKind = Literal[
    "mujoco_error",
    "mujoco_warning",
    "non_finite",
    "flipped",
    "on_floor",
    "left_ground",
    "no_footholds",
    "sliding_back",
]
FAILURE_KINDS: tuple[FailureKind, ...] = get_args(FailureKind)
NUMERICAL_FAILURES: frozenset[str] = frozenset({"mujoco_error", "mujoco_warning", "non_finite"})
SANITY_FAILURES: frozenset[str] = frozenset({"left_ground", "no_footholds", "sliding_back"})
# what the insect did, per physical failure kind: the words every face prints for a fall
INSECT_WORDS: dict[str, str] = {
    "flipped": "fell over",
    "on_floor": "fell over",
    "left_ground": "left the ground",
    "no_footholds": "lost every foothold",
    "sliding_back": "slid backwards",
}

# Physical sanity, checked every control period (`guard.guard_codes`), each from what sound runs
# do (3 s at slopes -30/0/+30 deg, beta 0.56-0.80, 1-12 g, Delta31 1.9 and 3.0):
# - left_ground: the lowest coxa attachment higher above the floor than a leg reaches
#   (`leg_reach`): no foot can touch, a geometric fact, no margin needed (sound runs keep the
#   body centre at 6.6-6.9 mm; the reach is 12.95 mm).
# - no_footholds: no leg in stance for NO_FOOTHOLD_S: sound runs always had a leg in stance
#   (longest all-swing spell 0 ms; 28 ms in runs already sliding downhill), and 0.1 s is three
#   swing durations (T_sw 34 ms).
NO_FOOTHOLD_S = 0.1
# - sliding_back: the body's mean velocity along the walking direction over a window of
#   SLIDE_WINDOW_S below -SLIDE_BACK_SPEED_M_S. 0.25 s spans a whole gait cycle up to beta 0.86
#   (T = 34 ms / (1 - beta)), so the in-cycle surges average out. Runs that walk never went
#   slower than -1.7 cm/s over any such window (uphill 30 deg, 12 g, feet slipping 1.4
#   strokes); runs that slide went -13.7 to -53 cm/s (and 89.9 deg: -120 cm/s). 5 cm/s sits
#   about 3x beyond the first and below the second, and is faster than the model walks forward
#   at any beta >= 0.56 (eq. 2: 4.6 cm/s).
SLIDE_WINDOW_S = 0.25
SLIDE_BACK_SPEED_M_S = 0.05


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
        # a flip or a fall may be a blow-up at a coarse step (euler at 1e-3 s flips in 3 ms);
        # the sanity kinds are checked only on a body that is upright and above the floor
        what = "run stopped" if self.kind in SANITY_FAILURES else "simulation diverged"
        return (
            f"{what} at t = {self.time_s:.4f} s (integrator {self.integrator}, "
            f"dt {self.dt_s:.3g} s): {self.reason}"
        )

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


class SimulationDiverged(RuntimeError):
    """A simulation left the physically meaningful region; it returns no numbers."""

    def __init__(self, failure: RunFailure) -> None:
        self.failure = failure
        super().__init__(str(failure))


def _plain(value: Any) -> Any:
    """A record's value as plain JSON types (arrays as lists, bool arrays as 0/1, tuples of
    arrays as lists of lists, a failure as its dict)."""
    if isinstance(value, np.ndarray):
        return (value.astype(int) if value.dtype == np.bool_ else value).tolist()
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    if isinstance(value, RunFailure):
        return value.to_dict()
    return value


def _fields_plain(record: Any) -> dict[str, Any]:
    """Every field of a record dataclass by name, as plain JSON types: what `summary` and
    `to_dict` say is generated from the records' fields, so a new field reaches them."""
    return {f.name: _plain(getattr(record, f.name)) for f in fields(record)}


@dataclass(frozen=True)
class RunEvents:
    """What happened in a run, at the moments it happened."""

    # Delta31 = phi3 - phi1 (mod 2 pi) just after each leg-1 touchdown, and when it happened
    d31: np.ndarray
    d31_times_s: np.ndarray
    touchdowns_s: tuple[np.ndarray, ...]  # per leg: touchdown times
    touchdown_phases: tuple[np.ndarray, ...]  # per leg: phase at touchdown, before resetting
    liftoffs_s: tuple[np.ndarray, ...]  # per leg: lift-off times

    @classmethod
    def none(cls) -> RunEvents:
        empty = np.zeros(0)
        legs = tuple(empty for _ in range(6))
        return cls(empty, empty, legs, legs, legs)


@dataclass(frozen=True)
class RunSeries:
    """What a run recorded every `record_dt_s` (empty when it was not recorded)."""

    times_s: np.ndarray  # (T,)
    stance: np.ndarray  # (T, 6) bool, paper leg order 1..6
    body_pos_m: np.ndarray  # (T, 3), world frame, x along the slope
    body_vel_m_s: np.ndarray  # (T, 3)
    body_quat: np.ndarray  # (T, 4) w, x, y, z

    def copy(self) -> RunSeries:
        """Copies of every series (a recorder hands out views into its buffers)."""
        return RunSeries(*(np.array(getattr(self, f.name)) for f in fields(self)))

    @classmethod
    def none(cls) -> RunSeries:
        return cls(np.zeros(0), np.zeros((0, 6), dtype=np.bool_), np.zeros((0, 3)),
                   np.zeros((0, 3)), np.zeros((0, 4)))  # fmt: skip


@dataclass(frozen=True)
class RunMeasures:
    """What a run's records mean, computed once (`records.assemble_result`); None where a
    failed run gives no numbers."""

    # where the run ends (circular mean of its last quarter) and, if it has settled by THE rule
    # (`gait.settling`: drift per cycle over the last quarter), its gait; else "not settled"
    d31_final: float | None = None
    gait: str | None = None
    settled: bool = False  # `gait.settling` of d31
    drift_per_cycle: float | None = None  # over the last quarter, rad per leg-1 touchdown
    settled_why: str = ""  # why not settled, in words ("" if settled)
    # the simulated length asked for: the spec's duration, or the time the run stopped
    # settled (`RunSpec.stop_if_settled_s`); a failed run ended earlier (`failure.time_s`)
    duration_s: float | None = None
    speed_cm_s: float | None = None  # along the body's heading (`gait.forward_speed`)
    duty_factor_measured: float | None = None
    slip_fraction: float | None = None  # median foot slip per stance / stroke D
    # median share of the swing done at touchdown (1 = at the AEP), `gait.landing_share`
    landing_swing_share: float | None = None
    # stance feet that rose more than `lift_clearance` and pressed in again, per touchdown:
    # ~0.1-0.4 on the defaults, > 2 where a coarse step makes the contact chatter
    retouches_per_stance: float | None = None
    # what the numbers say about themselves (`gait.run_warnings`): a duty factor off beta,
    # feet landing far from the AEP, a step coarser than the converged default
    warnings: tuple[str, ...] = ()


@dataclass(frozen=True)
class RunResult:
    """Everything one run gives back: what was asked (spec, numerics), what happened
    (`events`), what was recorded (`series`), what it means (`measures`), and the failure
    that stopped it, if any. A failed run (`failed`) has empty records and no measures."""

    spec: RunSpec
    integrator: str
    dt_s: float
    control_dt_s: float
    events: RunEvents
    series: RunSeries
    measures: RunMeasures
    failure: RunFailure | None = None

    @classmethod
    def failed(
        cls,
        spec: RunSpec,
        integrator: str,
        dt_s: float,
        control_dt_s: float,
        failure: RunFailure,
        duration_s: float | None = None,
    ) -> RunResult:
        """A run that left the physically meaningful region: no numbers, only why."""
        return cls(spec, integrator, dt_s, control_dt_s, RunEvents.none(), RunSeries.none(),
                   RunMeasures(duration_s=duration_s), failure)  # fmt: skip

    @property
    def error(self) -> str | None:
        """The failure in words (None for a run that finished)."""
        return None if self.failure is None else str(self.failure)

    @property
    def diverged(self) -> bool:
        return self.failure is not None

    def summary(self) -> dict[str, Any]:
        """The CLI's `--json` object, plain JSON types only: beta, Delta31 at every leg-1
        touchdown, every measure, and the failure (generated from `RunMeasures`' fields)."""
        return {
            "beta": self.spec.beta,
            "d31": _plain(self.events.d31),
            **_fields_plain(self.measures),
            "diverged": self.diverged,
            "error": self.error,
            "failure": _plain(self.failure),
        }

    def to_dict(self) -> dict[str, Any]:
        """Summary plus the spec, the numerics, every event and the time series, for storage
        and plotting (generated from the records' fields)."""
        return {
            **self.summary(),
            "spec": self.spec.model_dump(),
            "integrator": self.integrator,
            "dt_s": self.dt_s,
            "control_dt_s": self.control_dt_s,
            **_fields_plain(self.events),
            **_fields_plain(self.series),
        }

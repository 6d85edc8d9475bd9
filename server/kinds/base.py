"""What every job kind is: the request models' bases and `Kind`, the four things a kind module
exports as `KIND` (its request model, its runner, its record columns, its figure).

Job specs are strict (no coercion from strings, no unknown fields, no NaN) because a job runs
minutes after it was accepted: everything that can be refused must be refused at the door, with
a message naming the field and its allowed range. The rules are the core's own
(`sim_core.contract`: RunSpec's ranges and defaults, the integrators with their measured step
limits, the run's numerics): the kinds compose them and state only tighter bounds, each with its
reason. The contract loads without MuJoCo, so validating a request never waits on the physics
engine.
"""

from __future__ import annotations

import types
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Generic, TypeVar, Union, get_args, get_origin

from pydantic import BaseModel, ConfigDict, Field, ValidationInfo, create_model, field_validator

from server.kinds.bounds import (
    BETA_BOUNDS,
    DT_REASON,
    MAX_DT_S,
    IntLike,
    bounded,
    core_field,
    tidy,
)
from server.kinds.provenance import Provenance
from sim_core.contract import (
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    INTEGRATORS,
    ModelChoice,
    RunSpec,
    RunTemplate,
    control_problem,
    cost_problem,
    numerics_problem,
    resolve_numerics,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from server.kinds.compute import Compute

Progress = Callable[[float], None]


class JobFailed(Exception):
    """A refusal or failure whose message is meant for the client, as is."""


def step_weight(spec: dict[str, Any]) -> float:
    """Physics steps per simulated second of a job spec (its integrator, dt_s, control_dt_s,
    possibly null or absent) against the default step's: 1 at the default, 10 at 5e-6 s. The
    job-size limit and the time estimates (`server.estimates`) scale with it."""
    dt = resolve_numerics(spec.get("integrator"), spec.get("dt_s"), spec.get("control_dt_s"))[1]
    return DEFAULT_DT_S / dt


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True)


# The run's numerics, as the cross-field rules and the cost estimates read them.
NUMERICS = ("integrator", "dt_s", "control_dt_s")
# What the API states about a template field beyond the core's (each with its reason): a
# tighter bound, or words for a null.
TIGHTER: dict[str, dict[str, Any]] = {"dt_s": {"le": MAX_DT_S, "why": DT_REASON}}
INTEGRATOR_HELP = (
    f"MuJoCo integrator; allowed: {', '.join(INTEGRATORS)} or null (the default, "
    f"{DEFAULT_INTEGRATOR})"
)


def _numeric(annotation: Any) -> tuple[bool, bool]:
    """(whether a field is a number, whether it may be null) from its annotation."""
    args = [a for a in get_args(annotation) if a is not type(None)]
    nullable = get_origin(annotation) in (Union, types.UnionType) and len(args) == 1
    inner = args[0] if nullable else annotation
    return inner in (float, int), nullable


def template_field(name: str) -> tuple[Any, Any]:
    """A request field that is the run template's `name` (`sim_core.contract.RunTemplate`,
    RunSpec's fields bar the per-run ones): its type, default, words and bounds read from
    RunSpec (`core_field`), with the API's tighter bounds (`TIGHTER`). Every one is validated
    as given and as defaulted, so a default that clashes with a given value is refused too."""
    info = RunTemplate.model_fields[name]
    if name == "integrator":
        allowed = f"{', '.join(INTEGRATORS)} or null"
        help_ = Field(
            info.default, description=INTEGRATOR_HELP, json_schema_extra={"allowed": allowed}
        )
        return info.annotation, help_
    number, nullable = _numeric(info.annotation)
    if not number:  # a switch or a choice: RunSpec's default and words
        return info.annotation, Field(info.default, description=info.description)
    field = core_field(name, nullable=nullable, validate_default=True, **TIGHTER.get(name, {}))
    return info.annotation, field


class PhysicsRules(ModelChoice, Strict):
    """Fields every kind shares: the model's (`ModelChoice`: ground, a named setting, leaves
    by name, every one reaching the core's `ModelParams`) and the run template's
    (`RunTemplate`: every field of `sim_core.RunSpec` bar what a job sets run by run, added
    as `Physics`), from which the job composes each run's spec (`spec`), so no field of the
    spec is left behind.

    Cross-field rules run as field validators on the later field (so the 422 names it) with
    `validate_default`, so a default that clashes with a given value is refused too. Each
    kind adds `kind: Literal["<name>"] = "<name>"`, the tag of the request union.
    """

    @classmethod
    def kind_name(cls) -> str:
        """The kind's tag (`kind` in a request), the default of the subclass's `kind` field."""
        return str(cls.model_fields["kind"].default)

    @field_validator("dt_s", check_fields=False)
    @classmethod
    def _stable_for_the_integrator(cls, v: float | None, info: ValidationInfo) -> Any:
        if "integrator" not in info.data:
            return v  # the integrator itself was refused; that error says enough
        problem = numerics_problem(info.data.get("integrator"), v)
        if problem:
            raise ValueError(problem)
        return v

    @field_validator("control_dt_s", check_fields=False)
    @classmethod
    def _control_not_faster_than_physics(cls, v: float | None, info: ValidationInfo) -> Any:
        # a field validator (not a model one) so the 422 names control_dt_s itself
        if "dt_s" not in info.data:
            return v  # the step itself was refused; that error says enough
        problem = control_problem(info.data.get("dt_s"), v)
        if problem:
            raise ValueError(problem)
        return v

    def template(self) -> RunTemplate:
        """The job's run template: its fields that are the template's, as the core's type."""
        return RunTemplate.model_validate({n: getattr(self, n) for n in RunTemplate.model_fields})

    def spec(self, **per_run: Any) -> RunSpec:
        """The RunSpec of one of the job's runs: its template and `per_run` on top
        (`RunTemplate.spec`; without arguments, the template read as a RunSpec)."""
        return self.template().spec(**per_run)

    def effective_control_dt_s(self) -> float:
        return resolve_numerics(**self.spec_numerics())[2]

    def effective_dt_s(self) -> float:
        return resolve_numerics(**self.spec_numerics())[1]

    def keeps_series(self) -> bool:
        return False

    def cost_problem(self) -> str | None:
        """The core's cost rule for the whole job (`sim_core.contract.cost_problem`): steps per
        run and the memory of all its runs at once; None if it fits."""
        return cost_problem(
            self.sim_seconds_per_run(), **self.spec_numerics(),
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
        """The job's integrator, dt_s and control_dt_s (each possibly null), in that order."""
        return {n: getattr(self, n) for n in NUMERICS}

    def size_sim_seconds(self) -> float:
        """What the job-size limit (max_job_sim_seconds) counts: simulated seconds summed over
        runs, a finer step than the default counted as that many more (a coarser one as 1)."""
        return self.total_sim_seconds() * max(1.0, self.step_weight())

    def varied_conditions(self) -> tuple[str, ...]:
        """The conditions (body_mass_g, slope_deg) this job varies row by row, which its
        provenance leaves to the rows (`server.kinds.provenance`); none for most kinds."""
        return ()


if TYPE_CHECKING:  # generated below; type checkers read the template's fields via `spec()`
    Physics = PhysicsRules
else:
    Physics = create_model(
        "Physics",
        __base__=PhysicsRules,
        __module__=__name__,
        __doc__=PhysicsRules.__doc__,
        **{name: template_field(name) for name in RunTemplate.model_fields},
    )


def run_cost_problem(duration_s: float, info: ValidationInfo) -> str | None:
    """The core's per-run cost rule (the CLI's too) once the numerics fields are valid."""
    if not {"integrator", "dt_s", "control_dt_s"} <= set(info.data):
        return None  # a numerics field was refused; that error says enough
    d = info.data
    return cost_problem(duration_s, d["integrator"], d["dt_s"], d["control_dt_s"])


class Timed(Physics):
    """Kinds whose runs last a fixed `duration_s`."""

    duration_s: float = core_field("duration_s")

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
            problem = run_cost_problem(v, info)
            if problem:
                raise ValueError(problem)
        return v

    def sim_seconds_per_run(self) -> float:
        return self.duration_s


class BetaRange(Strict):
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


class Row(BaseModel):
    """One flat row of a kind's `records` (or of another of its tables): what the CSV export
    and the figure read. Each kind declares its row model; its fields are the table's columns
    (`Kind.columns`), so a column is declared once, with its type."""

    model_config = ConfigDict(extra="forbid")


class Result(BaseModel):
    """What a kind's runner returns: the `result` of GET /v1/jobs/{id}/result, one model per
    kind (tagged by `kind`), so the result's schema is in OpenAPI and mypy follows it from the
    runner to the route. A top-level null (an optional table left out) is not stored."""

    model_config = ConfigDict(extra="forbid")

    records: Sequence[Row] = Field(
        description="one flat row per run, grid point or sample (the kind's row model; the CSV "
        "export with table=records)"
    )
    provenance: Provenance | None = Field(
        None,
        description="the physics and conditions the job ran under (also the columns every CSV "
        "table of the job ends with); null for results stored before it was recorded",
    )


J = TypeVar("J", bound=Physics)
Runner = Callable[[J, "Compute"], Result]
Draw = Callable[["Figure", dict[str, Any], dict[str, Any]], None]


@dataclass(frozen=True)
class Kind(Generic[J]):
    """One job kind, as its module `server/kinds/<name>.py` exports it (`KIND`).

    model: the request model (a `Physics` subclass with `kind: Literal["<name>"]`).
    run: `run(job, compute) -> result`, called in a worker process only: the kind's
        `Result` (a `records` list of flat rows, which the CSV export and the figure read, plus
        whatever else the kind keeps); its simulations go through `compute`
        (`server.kinds.compute`: the shared result cache, on this worker or a cluster), which
        also carries the job's progress; it raises `JobFailed` rather than return numbers from
        a failed simulation.
    result: the kind's `Result` model (its schema is the result's in OpenAPI).
    row: the model of one row of `records`: its fields are the table's columns (`columns`, so
        that an empty table still has its header).
    tables: the kind's other tables, kept under the result's `series` when asked for (name ->
        row model; the CSV export's `table`); none for most kinds.
    draw: `draw(fig, spec, result)` draws the kind's figure on a matplotlib Figure (6.4 x 4.8
        in unless it resizes it), from the stored spec and result.
    """

    model: type[J]
    run: Runner[J]
    result: type[Result]
    row: type[Row]
    draw: Draw
    tables: dict[str, type[Row]] = field(default_factory=dict)

    @property
    def name(self) -> str:
        return self.model.kind_name()

    @property
    def columns(self) -> tuple[str, ...]:
        """The columns of `records`: its row model's fields, in their order."""
        return tuple(self.row.model_fields)

    def table_columns(self, table: str) -> tuple[str, ...]:
        """The columns of another table (`tables`), none for a table the kind has not."""
        row = self.tables.get(table)
        return () if row is None else tuple(row.model_fields)

"""`hysteresis`: the paper's Figs. 6a and 9 protocol in one run, the core's `Ramp` (a parameter
ramped from `start` to `turn` and back), Delta31 recorded against the value it had at each
touchdown."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Annotated, Any, Literal, get_type_hints

from pydantic import (
    BeforeValidator,
    Field,
    ValidationError,
    ValidationInfo,
    create_model,
    field_validator,
    model_validator,
)

import sim_core
from server.kinds.base import Kind, Physics, Result, Row, Strict, run_cost_problem
from server.kinds.bounds import (
    BETA_BOUNDS,
    BETA_DEFAULT,
    D31,
    DURATION_BOUNDS,
    SWEEP_RANGES,
    Bounds,
    bounded,
    in_range,
    range_text,
)
from server.kinds.common import d31_axis, failed, paper_transitions
from server.kinds.compute import Compute
from sim_core.contract import Ramp, RampParam, SweepSummary

if TYPE_CHECKING:
    from matplotlib.figure import Figure

MAX_SWEEP_S = DURATION_BOUNDS["le"]
# the schedule's own bounds: a hold long enough to settle, each leg at most one run's share
HOLD_BOUNDS: Bounds = {"gt": 0.0, "le": 60.0}
RAMP_BOUNDS: Bounds = {"gt": 0.0, "le": 280.0}
RAMP_HELP = (
    "the sweep's schedule, the core's `Ramp`: hold `param` at `start` for `hold_s`, ramp it to "
    "`turn` in `ramp_s`, back to `start` in `ramp_s`, hold again. param: beta, body_mass_g or "
    "slope_deg (its `start` wins over the job's field of that name); start, turn: in the range "
    "of the swept field ("
    + ", ".join(f"{k} {range_text('x', **b)}" for k, b in SWEEP_RANGES.items())
    + "), turn != start (Fig. 6a: beta 0.70 -> 0.62); "
    + range_text("hold_s", **HOLD_BOUNDS)
    + " s; "
    + range_text("ramp_s", **RAMP_BOUNDS)
    + f" s; 2 x hold_s + 2 x ramp_s <= {MAX_SWEEP_S:g} s"
)
# The request's shape before the ramp was the core's `Ramp` (issue 53): flat fields, `parameter`
# for `param`, with these defaults. Accepted for one release (docs/API.md, "Changelog"); a job
# stored in that shape by an older server still runs.
FLAT_FIELDS = ("parameter", "start", "turn", "hold_s", "ramp_s")
FLAT_DEFAULTS: dict[str, Any] = {"parameter": "beta", "hold_s": 5.0, "ramp_s": 30.0}

# The core's `Ramp` as a strict model, generated from its fields (strict mode refuses a plain
# dict for a dataclass, and a dataclass has no `extra="forbid"`): what a request's `ramp` is
# checked against before it becomes the core's `Ramp`.
_RAMP_TYPES = get_type_hints(Ramp)
RampFields = create_model(
    "RampFields",
    __base__=Strict,
    **{f.name: (_RAMP_TYPES[f.name], ...) for f in dataclasses.fields(Ramp)},  # type: ignore[call-overload]
)


def _a_ramp(value: Any) -> Any:
    """A request's `ramp` (a JSON object) as the core's `Ramp`, its fields checked strictly
    (no strings for numbers, no NaN, no unknown field): the 422 names the field."""
    if isinstance(value, Ramp):
        return value
    try:
        checked = RampFields.model_validate(value)
    except ValidationError as exc:
        raise ValueError("; ".join(
            f"ramp.{'.'.join(str(x) for x in e['loc'])}: {e['msg']}" if e["loc"] else e["msg"]
            for e in exc.errors()
        )) from None  # fmt: skip
    return Ramp(**dict(checked))


class HysteresisJob(Physics):
    """The paper's Figs. 6a and 9 protocol in one run: the core's `Ramp` (`ramp`: hold
    `param` at `start` for `hold_s`, ramp it to `turn` in `ramp_s`, back to `start` in
    `ramp_s`, hold again), recording Delta31 at every leg-1 touchdown against the value it had
    then (`sim_core.sweep`). Deprecated for one release: the flat fields `parameter`, `start`,
    `turn`, `hold_s`, `ramp_s` instead of `ramp` (docs/API.md, "Changelog")."""

    kind: Literal["hysteresis"] = "hysteresis"
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
    ramp: Annotated[Ramp, BeforeValidator(_a_ramp)] = Field(
        description=RAMP_HELP, json_schema_extra={"allowed": RAMP_HELP}
    )

    @model_validator(mode="before")
    @classmethod
    def _flat_fields_as_a_ramp(cls, data: Any) -> Any:
        """The deprecated flat shape (FLAT_FIELDS) read as a `ramp`, with its old defaults."""
        if not isinstance(data, dict) or not any(k in data for k in FLAT_FIELDS):
            return data
        if "ramp" in data:
            given = ", ".join(k for k in FLAT_FIELDS if k in data)
            raise ValueError(f"give the schedule as `ramp` only; {given} are its deprecated "
                             "flat form, not accepted beside it")  # fmt: skip
        flat = FLAT_DEFAULTS | {k: data[k] for k in FLAT_FIELDS if k in data}
        ramp = {"param": flat.pop("parameter"), **flat}
        return {k: v for k, v in data.items() if k not in FLAT_FIELDS} | {"ramp": ramp}

    @field_validator("ramp")
    @classmethod
    def _a_sweep_one_run_can_hold(cls, v: Ramp, info: ValidationInfo) -> Ramp:
        bounds = SWEEP_RANGES[v.param]
        for name, x in (("start", v.start), ("turn", v.turn)):
            if not in_range(x, bounds):
                raise ValueError(f"ramp.{name} ({x:g}) is outside the range of {v.param}: "
                                 f"{range_text(v.param, **bounds)}")  # fmt: skip
        if v.turn == v.start:
            raise ValueError(f"ramp.turn ({v.turn:g}) must differ from ramp.start: nothing "
                             "would be swept")  # fmt: skip
        for name, x, b in (("hold_s", v.hold_s, HOLD_BOUNDS), ("ramp_s", v.ramp_s, RAMP_BOUNDS)):
            if not in_range(x, b):
                raise ValueError(f"ramp.{name} ({x:g}) is outside {range_text(name, **b)}")
        if v.duration_s > MAX_SWEEP_S:
            raise ValueError(
                f"the sweep lasts 2 x hold_s + 2 x ramp_s = {v.duration_s:g} s; at most "
                f"{MAX_SWEEP_S:g} s (one run's limit)"
            )
        problem = run_cost_problem(v.duration_s, info)
        if problem:
            raise ValueError(problem)
        return v

    def run_count(self) -> int:
        return 1

    def varied_conditions(self) -> tuple[str, ...]:
        """A ramped mass or slope is the rows' `value`, not the job's field."""
        return (self.ramp.param,)

    def sim_seconds_per_run(self) -> float:
        return self.ramp.duration_s

    def start_spec(self) -> sim_core.RunSpec:
        """The RunSpec of the sweep's start: the job's template, beta and start, the ramped
        field at the ramp's start, the length the schedule's."""
        start = {"beta": self.beta, self.ramp.param: self.ramp.start}
        return self.spec(**start, d31_init=self.d31_init, duration_s=self.ramp.duration_s)


class HysteresisRow(Row):
    """Delta31 at one leg-1 touchdown of the sweep, against the ramped value then."""

    time_s: float = Field(description="when, s from the sweep's start")
    leg: Literal["first", "second"] = Field(
        description="the ramp's leg: first (start -> turn, the first hold included) or second "
        "(turn -> start, the last hold included)"
    )
    value: float = Field(description="the ramped parameter's value then")
    d31: float = Field(description="Delta31 just after the touchdown, rad")


class HysteresisJobResult(Result):
    """A hysteresis job's result: Delta31 at every leg-1 touchdown against the ramped value."""

    kind: Literal["hysteresis"] = "hysteresis"
    records: list[HysteresisRow]
    parameter: RampParam = Field(description="the ramped parameter")
    start: float = Field(description="its value at the start and the end")
    turn: float = Field(description="its value at the turn")
    summary: SweepSummary = Field(
        description="transitions on each leg of the ramp, the loop's width and whether it is a "
        "hysteresis loop (the core's sweep summary)"
    )


def run(job: HysteresisJob, compute: Compute) -> HysteresisJobResult:
    """Fig. 6a / 9: one run ramping `parameter` start -> turn -> start (the core's `sweep`, a
    ramp task through the shared cache, the key `reproduce`'s ramps have); Delta31 against the
    value at every leg-1 touchdown, and the transitions on each leg of the ramp."""
    sim = sim_core
    spec = job.start_spec()
    moving = compute.moving(1)
    ramp = job.ramp
    res = sim.sweep(
        spec,
        parameter=ramp.param,
        turn=ramp.turn,
        hold_s=ramp.hold_s,
        ramp_s=ramp.ramp_s,
        params=job.model_params(),
        progress=moving.on_progress,
        **compute.core(moving),
    )
    if res.failure is not None:
        raise failed(job, [("the sweep run", res.failure)], 1)
    turn_t = ramp.turn_time_s
    records = [
        {"time_s": t, "leg": "first" if t < turn_t else "second", "value": v, "d31": d}
        for t, v, d in zip(res.times_s, res.values, res.d31, strict=True)
    ]
    return HysteresisJobResult(
        parameter=ramp.param, start=ramp.start, turn=ramp.turn, summary=res.summary,
        records=records,
    )  # fmt: skip


def draw(fig: Figure, spec: dict[str, Any], result: dict[str, Any]) -> None:
    """Delta31 against the swept parameter, each leg of the ramp in its colour, with the
    transitions the summary found."""
    ax = fig.add_subplot()
    records = result.get("records", [])
    for leg, colour in (("first", "tab:blue"), ("second", "tab:red")):
        pts = [(r["value"], r["d31"]) for r in records if r["leg"] == leg]
        ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=6, color=colour,
                   label=f"{'start → turn' if leg == 'first' else 'turn → start'}")  # fmt: skip
    summary = result.get("summary") or {}
    for leg, style in (("first_leg", "--"), ("second_leg", ":")):
        for tr in summary.get(leg) or []:
            if isinstance(tr, dict) and tr.get("value") is not None:
                ax.axvline(tr["value"], ls=style, color="grey", lw=0.8)
    parameter = str(result.get("parameter", spec.get("parameter")))
    if parameter == "beta":  # the paper's Fig. 6a: its transitions beside the ramp's
        paper_transitions(ax)
    ax.set_xlabel(parameter)
    ax.set_ylabel("Δ31 (rad)")
    d31_axis(ax)
    ax.set_title(f"hysteresis sweep: {result.get('start')} → {result.get('turn')} → back")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)


KIND = Kind(model=HysteresisJob, run=run, result=HysteresisJobResult, row=HysteresisRow, draw=draw)

"""`hysteresis`: the paper's Figs. 6a and 9 protocol in one run, a parameter ramped from `start`
to `turn` and back, Delta31 recorded against the value it had at each touchdown."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field, ValidationInfo, field_validator

import sim_core
from server.kinds.base import Kind, Physics, Result, run_cost_problem
from server.kinds.bounds import (
    BETA_BOUNDS,
    BETA_DEFAULT,
    D31,
    DURATION_BOUNDS,
    SWEEP_RANGES,
    bounded,
    in_range,
    range_text,
)
from server.kinds.common import d31_axis, failed, paper_transitions
from server.kinds.compute import Compute
from sim_core.contract import RampParam

if TYPE_CHECKING:
    from matplotlib.figure import Figure

COLUMNS = ("time_s", "leg", "value", "d31")
SweptParameter = RampParam
MAX_SWEEP_S = DURATION_BOUNDS["le"]


class HysteresisJob(Physics):
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
        if not in_range(v, bounds):
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
            problem = run_cost_problem(2 * hold + 2 * v, info)
            if problem:
                raise ValueError(problem)
        return v

    def run_count(self) -> int:
        return 1

    def varied_conditions(self) -> tuple[str, ...]:
        """A ramped mass or slope is the rows' `value`, not the job's field."""
        return (self.parameter,)

    def sim_seconds_per_run(self) -> float:
        return 2.0 * self.hold_s + 2.0 * self.ramp_s

    def run_fields(self) -> dict[str, Any]:
        """The RunSpec of the sweep's start (its duration is set by the schedule)."""
        out = {**self.physics_fields(), "beta": self.beta, "d31_init": self.d31_init}
        out[self.parameter] = self.start
        out["duration_s"] = self.sim_seconds_per_run()
        return out


class HysteresisJobResult(Result):
    """A hysteresis job's result: Delta31 at every leg-1 touchdown against the ramped value."""

    kind: Literal["hysteresis"] = "hysteresis"
    parameter: RampParam = Field(description="the ramped parameter")
    start: float = Field(description="its value at the start and the end")
    turn: float = Field(description="its value at the turn")
    summary: dict[str, Any] = Field(
        description="transitions on each leg of the ramp, the loop's width and whether it is a "
        "hysteresis loop (the core's sweep summary)"
    )


def run(job: HysteresisJob, compute: Compute) -> HysteresisJobResult:
    """Fig. 6a / 9: one run ramping `parameter` start -> turn -> start (the core's `sweep`, a
    ramp task through the shared cache, the key `reproduce`'s ramps have); Delta31 against the
    value at every leg-1 touchdown, and the transitions on each leg of the ramp."""
    sim = sim_core
    spec = sim.RunSpec(**job.run_fields())
    moving = compute.moving(1)
    res = sim.sweep(
        spec,
        parameter=job.parameter,
        turn=job.turn,
        hold_s=job.hold_s,
        ramp_s=job.ramp_s,
        params=job.model_params(),
        progress=moving.on_progress,
        **compute.core(moving),
    )
    if res.failure is not None:
        raise failed(job, [("the sweep run", res.failure)], 1)
    turn_t = job.hold_s + job.ramp_s
    records = [
        {"time_s": t, "leg": "first" if t < turn_t else "second", "value": v, "d31": d}
        for t, v, d in zip(res.times_s, res.values, res.d31, strict=True)
    ]
    return HysteresisJobResult(
        parameter=job.parameter, start=job.start, turn=job.turn, summary=res.summary,
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
    ax.set_title(f"hysteresis sweep: {spec.get('start')} → {spec.get('turn')} → back")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)


KIND = Kind(model=HysteresisJob, run=run, result=HysteresisJobResult, columns=COLUMNS, draw=draw)

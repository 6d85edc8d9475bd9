"""The typed summaries the edges serve: one run's (`RunSummary`, what `RunResult.summary()`
returns), its whole record (`RunRecord`, `RunResult.to_dict()`) and a triangle sweep's
(`SweepSummary`, what `sweep_summary` returns: its transitions and loop).

Why generated: `summary()` and `to_dict()` are generated from the run's records' fields
(`RunMeasures`, `RunEvents`, `RunSeries`: sim_core/model/spec.py), so a new measure reaches
them with no other edit; their typed models are generated from the same fields here, so the new
measure is a new typed field of the REST results too (and of their OpenAPI schema), from the
one place it is declared. The few keys `summary()` adds itself (beta, Delta31 at each
touchdown, the failure) are declared here, in `summary()`'s order.

Defaults: every measure has one (`RunMeasures`' own), so a summary stored before a measure
existed still validates and, dumped with `exclude_unset`, keeps exactly the keys it had.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any, get_type_hints

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, create_model

from sim_core.model.spec import RunEvents, RunFailure, RunMeasures, RunSeries, RunSpec


class Summary(BaseModel):
    """A typed summary: unknown keys refused (a key nobody declared is a bug, not data)."""

    model_config = ConfigDict(extra="forbid")


# An array of a run's records as JSON: numbers per sample, or rows of them (stance as 0/1
# ints, positions as floats); the union keeps ints ints and floats floats (smart mode).
Array = list[float] | list[list[int]] | list[list[float]]


def _json_type(hint: Any) -> Any:
    """A record field's type as its JSON form (`spec._plain`): arrays as lists, a tuple of
    per-leg arrays as a list of lists, a tuple of strings as a list."""
    if hint is np.ndarray:
        return Array
    if hint == tuple[np.ndarray, ...]:
        return list[list[float]]
    if hint == tuple[str, ...]:
        return list[str]
    return hint


def _fields_of(record: type[Any], *, defaults: bool) -> dict[str, Any]:
    """A record dataclass's fields as `create_model` field definitions, in its order."""
    hints = get_type_hints(record)
    out: dict[str, Any] = {}
    for f in dataclasses.fields(record):
        default = f.default if defaults and f.default is not dataclasses.MISSING else ...
        out[f.name] = (_json_type(hints[f.name]), default)
    return out


_SUMMARY_FIELDS: dict[str, Any] = {
    "beta": (float, Field(description="the run's duty factor (its start, for a ramp)")),
    "d31": (list[float], Field(description="Delta31 at every leg-1 touchdown, rad")),
    **_fields_of(RunMeasures, defaults=True),
    "diverged": (bool, Field(False, description="the run left the physical region")),
    "error": (str | None, Field(None, description="its failure in words")),
    "failure": (RunFailure | None, Field(None, description="its failure as a value")),
}
_RECORD_FIELDS: dict[str, Any] = {
    "spec": (RunSpec, ...),
    "integrator": (str, ...),
    "dt_s": (float, ...),
    "control_dt_s": (float, ...),
    **_fields_of(RunEvents, defaults=False),
    **_fields_of(RunSeries, defaults=False),
}

if TYPE_CHECKING:  # generated below; type checkers see typed models whose fields they skip

    class RunSummary(Summary):
        """One run's summary (`RunResult.summary()`)."""

    class RunRecord(RunSummary):
        """One run's whole record (`RunResult.to_dict()`)."""

else:
    RunSummary = create_model(
        "RunSummary",
        __base__=Summary,
        __doc__="One run's summary (`RunResult.summary()`): beta, Delta31 at every leg-1 "
        "touchdown, every measure of `RunMeasures` and the failure, if any.",
        **_SUMMARY_FIELDS,
    )
    RunRecord = create_model(
        "RunRecord",
        __base__=RunSummary,
        __doc__="One run's whole record (`RunResult.to_dict()`): its summary, spec and "
        "numerics, every event and the sampled time series.",
        **_RECORD_FIELDS,
    )

# the measures a summary holds, in its order (the REST kinds' summary rows read them)
SUMMARY_MEASURES: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(RunMeasures))


class SweepTransition(Summary):
    """A gait switch on one leg of a triangle sweep (`sweep_summary`)."""

    value: float = Field(description="the ramped parameter where the gait switched")
    time_s: float = Field(description="when, s from the sweep's start")
    before: str = Field(description="the gait before")
    after: str = Field(description="the gait after")


class SweepSummary(Summary):
    """A triangle sweep start -> turn -> start read as the paper reads Figs. 6a and 9: the
    transitions on each leg, the loop's width and whether it is a hysteresis loop."""

    start: float = Field(description="the value held first and last")
    turn: float = Field(description="the value the ramp turns at")
    first_leg: list[SweepTransition] = Field(description="transitions start -> turn")
    second_leg: list[SweepTransition] = Field(description="transitions turn -> start")
    width: float | None = Field(
        description="|first leg's switch - second leg's|, null unless both legs switched"
    )
    loop: bool | None = Field(
        description="the first leg's switch lies beyond the second's in its direction (the "
        "system stayed on its branch both ways); null unless both legs switched"
    )
    gait_at_start: str = Field(description="the gait walked at the end of the first hold")
    gait_at_turn: str = Field(description="the gait walked at the turn")
    gait_at_end: str = Field(description="the gait walked at the end")

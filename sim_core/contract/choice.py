"""The model's parameters as an edge takes them: a ground, an optional named setting, and
leaves by their names on top (`ModelChoice`).

Why one type: `insect-gait run`, every REST job, the viewer's start flags, its settings file,
its exports and its job submissions all pass the same three things, and each must refuse an
unknown leaf or an out-of-range value in the same words. The leaves are validated by building
the `ModelParams` they make (`ModelParams.of`: the model's own ranges, no copy of them here),
and what a run used is recorded as the leaves off their defaults (`leaf_values`, the result
cache's key part), so a setting and the same leaves typed out read alike.

The leaves a run's spec has a field of its own for (`body_mass` -> `body_mass_g`, `integrator`,
`dt` -> `dt_s`, `control_dt` -> `control_dt_s`) and the ground (a field of its own here) are
refused as leaves, naming the field to use: the spec's field wins inside the core, so a leaf
would be silently overridden, and the edges' step rules are checked on the fields.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Self

from pydantic import BaseModel, ConfigDict, Field, ValidationError, ValidationInfo, field_validator

from sim_core.contract.defaults import GROUND_HELP
from sim_core.model.params import (
    GROUND_DEFAULT,
    GROUND_ONLY,
    GROUNDS,
    PARAMETER_NAMES,
    ModelParams,
    leaf_values,
)
from sim_core.model.settings import NAMED_SETTINGS

Leaf = float | int | str | bool

# leaf -> the field an edge takes it by instead (the run's spec, or the ground's own field)
OWN_FIELD: dict[str, str] = {
    "body_mass": "body_mass_g",
    "integrator": "integrator",
    "dt": "dt_s",
    "control_dt": "control_dt_s",
    "ground": "ground",
}


def _close(name: str) -> str:
    """A hint for a mistyped leaf: the known names sharing its first word, else where all
    are listed."""
    head = name.split("_")[0]
    near = [n for n in PARAMETER_NAMES if n.split("_")[0] == head and n not in OWN_FIELD]
    if near:
        return f"did you mean {', '.join(near[:6])}?"
    return "the names are listed by `insect-gait params` and GET /v1/model"


class ModelChoice(BaseModel):
    """The model parameters of a run or job: its ground, a named setting (NAMED_SETTINGS,
    e.g. "soft_legs") or none, and leaves by name on top of both. Strict like the jobs (no
    coercion from strings, no NaN): the CLI parses its `--param NAME=VALUE` into typed values
    first (`sim_core.cli`)."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True)

    ground: str = Field(
        GROUND_DEFAULT,
        description=GROUND_HELP,
        json_schema_extra={"allowed": " or ".join(GROUNDS), "enum": list(GROUNDS)},
    )
    setting: str | None = Field(
        None,
        description="a named model setting (a campaign's regime of invented parameters), "
        f"one of {', '.join(sorted(NAMED_SETTINGS))}, or null: the defaults",
        json_schema_extra={"allowed": f"{', '.join(sorted(NAMED_SETTINGS))} or null"},
    )
    params: dict[str, Leaf] = Field(
        default_factory=dict,
        description="model parameters by their leaf names (GET /v1/model lists them with their "
        "values and reasons), on top of the setting, each in its range; the run's own fields "
        f"are refused here ({', '.join(f'{k} -> {v}' for k, v in OWN_FIELD.items())})",
    )

    @field_validator("ground")
    @classmethod
    def _a_known_ground(cls, v: str) -> str:
        if v not in GROUNDS:
            raise ValueError(f"ground must be one of {', '.join(GROUNDS)}; got {v!r}")
        return v

    @field_validator("setting")
    @classmethod
    def _a_known_setting(cls, v: str | None) -> str | None:
        if v is not None and v not in NAMED_SETTINGS:
            known = ", ".join(sorted(NAMED_SETTINGS))
            raise ValueError(f"no model setting {v!r}; known: {known} (or null)")
        return v

    @field_validator("params")
    @classmethod
    def _known_leaves_in_range(cls, v: dict[str, Leaf], info: ValidationInfo) -> dict[str, Leaf]:
        # a field validator (not a model one) so that a 422 names `params`; ground and setting
        # come first, so the leaves are checked on the ground and setting given
        for name in v:
            if name in OWN_FIELD:
                raise ValueError(
                    f"{name} is not taken as a model parameter here: use the field "
                    f"{OWN_FIELD[name]} (it would be overridden by it)"
                )
            if name not in PARAMETER_NAMES:
                raise ValueError(f"unknown model parameter {name!r}: {_close(name)}")
        if {"ground", "setting"} <= set(info.data):  # else that field's refusal says enough
            ground, setting = info.data["ground"], info.data["setting"]
            problem = _problem(_leaves(setting, v, ground), ground)
            if problem:
                raise ValueError(problem)
        return v

    def leaves(self) -> dict[str, Any]:
        """The leaves this choice sets: the setting's, the given ones on top, and the ground."""
        return _leaves(self.setting, self.params, self.ground)

    def model_params(self) -> ModelParams:
        """The core's parameters of this choice (validated when the choice was)."""
        return ModelParams.of(**self.leaves())

    def changed(self) -> dict[str, Any]:
        """The leaves off their defaults that this choice makes, by name (the ground left to
        its own field): what a record, an export and the viewer's panel show."""
        return changed_leaves(self.model_params())

    def words(self) -> str:
        """One line for a person: "soft_legs (kp_lift 0.00077, ...)", "kp_lift 0.001", or
        "defaults"."""
        changed = ", ".join(f"{k} {_shown(v)}" for k, v in sorted(self.changed().items()))
        if self.setting:
            return f"{self.setting} ({changed})" if changed else self.setting
        return changed or "defaults"

    def body(self) -> dict[str, Any]:
        """The choice as a job's or a settings file's fields, setting and params only where
        given (the ground always)."""
        return self.model_dump(mode="json", exclude_defaults=True) | {"ground": self.ground}

    @classmethod
    def read(cls, data: Mapping[str, Any]) -> Self:
        """The choice among a larger mapping's fields (a settings file, a switch's fields),
        absent ones at their defaults; a ValueError in one line naming each refused field
        ("params: unknown model parameter 'x': ...") otherwise."""
        try:
            return cls.model_validate({k: data[k] for k in cls.model_fields if k in data})
        except ValidationError as exc:
            words = [f"{'.'.join(map(str, e['loc']))}: {e['msg']}" for e in exc.errors()]
            raise ValueError("; ".join(words).replace("Value error, ", "")) from None


def changed_leaves(params: ModelParams) -> dict[str, Any]:
    """The leaves of `params` off their defaults, by name, the ground left to its own field:
    what a choice, a surface or an atlas records of the model it ran."""
    return {k: v for k, v in leaf_values(params).items() if k != "ground"}


def _leaves(setting: str | None, params: dict[str, Leaf], ground: str) -> dict[str, Any]:
    named = dict(NAMED_SETTINGS[setting]) if setting else {}
    return named | dict(params) | {"ground": ground}


def _problem(leaves: dict[str, Any], ground: str) -> str | None:
    """Why these leaves make no valid `ModelParams`, one clause per refused leaf naming it
    with the model's bound, or None."""
    try:  # strict: a number as a string, or true for a gain, is refused, not read
        ModelParams.model_validate(leaves, strict=True)
    except ValidationError as exc:
        return "; ".join(_leaf_error(err, ground) for err in exc.errors())
    return None


def _shown(v: Any) -> str:
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def _leaf_error(err: Any, ground: str) -> str:
    """One refused leaf in words naming it: its name and pydantic's sentence with the bound;
    a leaf of the other ground says which ground has it."""
    leaf = str(err["loc"][-1]) if err["loc"] else ""
    msg = str(err["msg"]).removeprefix("Value error, ")
    if err["type"] == "extra_forbidden":
        owner = [g for g, names in GROUND_ONLY.items() if leaf in names]
        where = f"a parameter of the {owner[0]} ground only" if owner else "not a parameter"
        return f"{leaf} is {where}; ground is {ground!r}"
    return f"{leaf}: {msg} (got {err.get('input')!r})" if leaf else msg

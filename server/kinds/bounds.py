"""Bounds as numbers and as words: every kind's ranges come from one set of numbers, which the
validator enforces and the schema and the 422 messages state ('0.5 < beta < 1').

The ranges are the core's (`sim_core.contract.RunSpec`), read from it, never retyped; a kind
states only tighter bounds, each with its reason. Nothing here loads MuJoCo.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, TypedDict

import annotated_types
from pydantic import BeforeValidator, Field

from sim_core.contract import (
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    MAX_STABLE_DT_S,
    MIN_DT_S,
    TWO_PI,
    RunSpec,
)

MAX_LIST = 1000  # hard cap on list lengths; the per-deployment cap is Settings.max_runs_per_job


class Bounds(TypedDict, total=False):
    """A field's bounds as pydantic's keyword arguments (any of gt, ge, lt, le)."""

    gt: float
    ge: float
    lt: float
    le: float


def _number(x: object) -> float:
    if isinstance(x, int | float):
        return float(x)
    raise TypeError(f"a bound of RunSpec is not a number: {x!r}")


def core_bounds(name: str) -> Bounds:
    """RunSpec's bounds on field `name`: the API's ranges are the core's, read from it."""
    out = Bounds()
    for m in RunSpec.model_fields[name].metadata:
        if isinstance(m, annotated_types.Gt):
            out["gt"] = _number(m.gt)
        elif isinstance(m, annotated_types.Ge):
            out["ge"] = _number(m.ge)
        elif isinstance(m, annotated_types.Lt):
            out["lt"] = _number(m.lt)
        elif isinstance(m, annotated_types.Le):
            out["le"] = _number(m.le)
    return out


def core_default(name: str) -> Any:
    return RunSpec.model_fields[name].default


# The grounds a job may walk on (`ModelParams.ground`, read from it) and the default's.
GROUND_HELP = (
    "the ground model: 'constraint' (MuJoCo's contact, the default) or 'penalty' (the paper's "
    "viscoelastic feet, which keep the heading on slopes: docs/MODEL.md, 'Slopes')"
)


def in_range(value: float, bounds: Bounds) -> bool:
    return (
        value > bounds.get("gt", -math.inf)
        and value >= bounds.get("ge", -math.inf)
        and value < bounds.get("lt", math.inf)
        and value <= bounds.get("le", math.inf)
    )


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
# the range each swept parameter (hysteresis, atlas) may take: the field of that name's
SWEEP_RANGES: dict[str, Bounds] = {
    "beta": BETA_BOUNDS,
    "body_mass_g": MASS_BOUNDS,
    "slope_deg": SLOPE_BOUNDS,
}


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


def core_field(
    name: str,
    *,
    why: str | None = None,
    nullable: bool = False,
    validate_default: bool = False,
    **tighter: float,
) -> Any:
    """A request field that is RunSpec's field `name`: its default, its words and its bounds
    (or `tighter` ones, stated with `why`), all read from RunSpec, declared there once."""
    info = RunSpec.model_fields[name]
    what = info.description or name
    if info.annotation is bool:
        return Field(info.default, description=what)
    bounds = Bounds(**core_bounds(name))
    bounds.update(tighter)  # type: ignore[typeddict-item]  # only gt, ge, lt, le are passed
    return bounded(
        info.default, name, what, **bounds, nullable=nullable, why=why,
        validate_default=validate_default,
    )  # fmt: skip


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

"""What made a job's numbers, stamped on its result and on every CSV table the API serves.

Why: the run and sweep tables carried beta and the start but not the mass, slope or ground
they walked under, and no export named the physics' version or the parameters' hash, so a CSV
read later (or beside a `reproduce` file) could not say which physics made it. The physics'
part is the core's `provenance` (`sim_core.contract`: the version, the parameters' hash as the
result cache keys it, the ground, the step), the same words a cached run and the viewer's export
use; the job adds its integrator, control step and the conditions it held.

A condition the job varies row by row (an atlas's axis, a hysteresis ramp's parameter) is left
blank here: its value is the row's own (`value`), never the job's field.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from pydantic import BaseModel, ConfigDict, Field

from sim_core.contract import provenance, resolve_numerics

if TYPE_CHECKING:
    from server.kinds.base import Physics


class Provenance(BaseModel):
    """The physics and the conditions a job ran under (recorded when it ran)."""

    model_config = ConfigDict(extra="forbid")

    physics_version: str = Field(description="the core's PHYSICS_VERSION the job ran with")
    params_hash: str = Field(
        description="12 hex digits of the non-default model parameters' hash, as the result "
        "cache keys runs (the ground included)"
    )
    ground: str = Field(description="the ground: constraint (MuJoCo's contact) or penalty")
    integrator: str = Field(description="the MuJoCo integrator in effect")
    dt_s: float = Field(description="the physics step in effect, s")
    control_dt_s: float = Field(description="the control period in effect, s")
    body_mass_g: float | None = Field(
        description="body mass, g (null where the job varies it row by row: see `value`)"
    )
    slope_deg: float | None = Field(
        description="slope, deg (null where the job varies it row by row: see `value`)"
    )
    setting: str | None = Field(
        None, description="the named model setting the job asked for (null: none)"
    )
    params: dict[str, float | int | str | bool] | None = Field(
        None,
        description="the model parameters off their defaults that the job ran with, by leaf "
        "name (a setting's included; {}: the defaults; null for results stored before they "
        "were recorded); the CSV column holds them as JSON",
    )


PROVENANCE_COLUMNS: tuple[str, ...] = tuple(Provenance.model_fields)


def job_provenance(job: Physics) -> Provenance:
    """The job's provenance: the core's physics words plus its numerics and held conditions."""
    integrator, dt_s, control_dt_s, _ = resolve_numerics(
        **job.spec_numerics(), params=job.model_params()
    )
    varied = job.varied_conditions()
    held = {k: None if k in varied else getattr(job, k) for k in ("body_mass_g", "slope_deg")}
    return Provenance(
        **provenance(job.model_params(), dt_s), integrator=integrator,
        control_dt_s=control_dt_s, **held, setting=job.setting, params=job.changed(),
    )  # fmt: skip


def stamped(
    rows: list[dict[str, Any]], columns: Sequence[str], found: dict[str, Any] | None
) -> tuple[list[dict[str, Any]], tuple[str, ...]]:
    """Rows with the provenance's columns after the table's own (a row's own value of a
    column wins, e.g. a finder row's body_mass_g), and the header with them; a result stored
    before provenance was recorded gets the columns blank (unknown, not guessed)."""
    header = (*columns, *(c for c in PROVENANCE_COLUMNS if c not in columns))
    extra = {c: _flat((found or {}).get(c)) for c in PROVENANCE_COLUMNS if c not in columns}
    return [{**row, **{k: v for k, v in extra.items() if k not in row}} for row in rows], header


def _flat(value: Any) -> Any:
    """A provenance value as one CSV cell: the parameters as JSON (readable back), others as
    they are."""
    return json.dumps(value, sort_keys=True) if isinstance(value, dict) else value

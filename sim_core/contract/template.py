"""One run template: `RunSpec` without what an instrument sets run by run (`RunTemplate`).

Why: a job, the drift surface, the atlas and the finder each run many walks that differ only
in the start, the duty factor, the length or the pin; everything else (the body, the slope,
phase resetting, the numerics, any run option added later) is the same for all of them. When
each of those callers spelled the shared fields out (`body_mass_g=..., slope_deg=...,
numerics=...`), a field nobody spelled was silently dropped: a surface job with phase
resetting off ran with it on. The template is generated from RunSpec's own fields, so a field
added to RunSpec is a field of the template (and of every REST job, which the server composes
from it) with no other edit; an instrument composes each run's spec from it (`spec`), so no
field can be left behind on the way.

`PER_RUN` names what the instruments set themselves, run by run: those are the template's
only gaps. The cross-field rules are RunSpec's, checked where a run's spec is composed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Self

from pydantic import BaseModel, ConfigDict, create_model

from sim_core.model.spec import RunSpec

# The fields an instrument sets run by run: the duty factor (a grid), the start, the length
# (and a short try inside it), and the drift surface's pin. Everything else is the template's.
PER_RUN: tuple[str, ...] = (
    "beta",
    "d31_init",
    "duration_s",
    "stop_if_settled_s",
    "pin_d31",
    "pin_gain_per_s",
)


class TemplateBase(BaseModel):
    """What a run template does, whatever its fields: compose a run's spec."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    def spec(self, **per_run: Any) -> RunSpec:
        """The RunSpec of one run: every field of this template, `per_run` on top (a per-run
        field, or a template field one run changes, as an atlas row its mass). Without
        arguments, the template read as a RunSpec (the per-run fields at RunSpec's defaults):
        its fields typed, its cross-field rules checked. ValidationError as RunSpec's."""
        return RunSpec(**(dict(self) | per_run))

    def replace(self, **fields: Any) -> Self:
        """This template with `fields` changed, validated (an atlas's row at its value)."""
        return self.model_validate(dict(self) | fields)

    @classmethod
    def of(cls, spec: RunSpec) -> Self:
        """The template of a spec: its fields bar the per-run ones."""
        return cls.model_validate({n: getattr(spec, n) for n in cls.model_fields})


if TYPE_CHECKING:  # generated below; type checkers read its fields through `spec()`

    class RunTemplate(TemplateBase):
        """RunSpec's fields bar `PER_RUN`."""

else:
    RunTemplate = create_model(
        "RunTemplate",
        __base__=TemplateBase,
        __module__=__name__,
        __doc__="A run template: every field of RunSpec bar the per-run ones (`PER_RUN`), "
        "with RunSpec's types, defaults, bounds and words.",
        **{n: (f.annotation, f) for n, f in RunSpec.model_fields.items() if n not in PER_RUN},
    )

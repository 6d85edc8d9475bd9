"""Named model settings: whole regimes of the invented parameters, one value a person can pass.

Why. A gait campaign's finding is a set of leaves, not one lever; naming the set keeps it
exactly as measured (docs/MODEL.md, "Named settings"; docs/studies/soft_legs.md) instead of
retyped from a journal into each script. A setting names only invented leaves: the paper's
masses, lengths, D, T_sw and gains K are never part of one. None is the default.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any

from sim_core.model.params import OURS, ModelParams

# The fifth study's soft legs (docs/studies/journal.md, 2026-11-24; issue 52, point 2): soft,
# well-damped servos with a low apex land early (0.95 of the swing), the regime in which the
# metachronal branch ends near the paper's 0.645. Each leaf with why it has this value:
SOFT_LEGS: MappingProxyType[str, float] = MappingProxyType(
    {
        "kp_yaw": 1.3e-3,  # joint 1 ~4x softer than the default: the yaw joint yields in stance
        "kd_yaw": 6.4e-6,  # joint 1 damping ~5x lower, keeping kd/kp ~5 ms
        "kp_lift": 7.7e-4,  # joints 2-3 ~4x softer: the body sags onto the stance legs
        "kd_lift": 1.9e-5,  # joints 2-3 damping ~6x higher: kd/kp ~25 ms, a slow lift
        "velocity_feedforward_lift": 1.0,  # lift damping on the tracking error (0 breaks it)
        "swing_height": 4e-4,  # a 0.4 mm apex (default 0.8): feet touch at 0.95 of the swing
        "com_offset_x": 0.0,  # centre of mass at the hips' centre (the default's +1 mm tips it)
        "stand_height": 7e-3,  # body 7 mm above the ground (default 6.5), the study's posture
    }
)

NAMED_SETTINGS: MappingProxyType[str, MappingProxyType[str, float]] = MappingProxyType(
    {"soft_legs": SOFT_LEGS}
)


def named_params(name: str, **leaves: Any) -> ModelParams:
    """The named setting `name` (NAMED_SETTINGS), with any further leaves on top, validated
    (`ModelParams.of`); an unknown name is refused with the known ones."""
    if name not in NAMED_SETTINGS:
        raise ValueError(f"no model setting {name!r}; known: {', '.join(sorted(NAMED_SETTINGS))}")
    return ModelParams.of(**(dict(NAMED_SETTINGS[name]) | leaves))


def _only_invented() -> None:
    """A named setting may hold invented leaves only (checked once, at import)."""
    fields: dict[str, Any] = {}
    for group in type(ModelParams()).model_fields.values():
        cls = group.annotation
        fields |= getattr(cls, "model_fields", {})
    for name, setting in NAMED_SETTINGS.items():
        for leaf in setting:
            extra = getattr(fields.get(leaf), "json_schema_extra", None)
            if extra != OURS:
                raise ValueError(f"setting {name!r}: {leaf} is not an invented parameter")


_only_invented()

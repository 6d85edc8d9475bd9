"""Which of the invented parameters were calibrated, and the +-10% robustness check's variants
of them (the developers' guide, "How to do science": a structure must survive +-10% of each
calibrated parameter): one definition for `insect-gait surface-check` (`surface_check`), the
finder's claims and the readings screen (`python -m lab finder-claims`, `readings --robust`).
"""

from __future__ import annotations

from collections.abc import Sequence

from sim_core.model.params import ModelParams

# The invented parameters that were chosen by calibration against the gait (docs/MODEL.md says
# so in each reason): fore-aft load sharing, stance height, lift-joint stiffness and damping,
# swing apex, sprawl.
CALIBRATED = ("com_offset_x", "stand_height", "kp_lift", "kd_lift", "swing_height", "foot_y")
SCALES = (0.9, 1.1)


def scaled_values(
    base: ModelParams, names: Sequence[str] = CALIBRATED, scales: Sequence[float] = SCALES
) -> list[tuple[str, dict[str, float]]]:
    """The +-10% check's variants: each of `names` at each scale of its value in `base`, as
    ("<param> x<scale>", {param: value})."""
    return [(f"{n} x{s:g}", {n: base.leaf(n) * s}) for n in names for s in scales]

"""The open parameters a search may move, each within a physically plausible range with the
reason for it (the paper states outcomes, not these values)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Range:
    low: float
    high: float
    log: bool
    reason: str


SEARCH_SPACE: dict[str, Range] = {
    "kp_lift": Range(5e-4, 2e-2, True, "static sag ~0.02-0.7 mm under a tripod's load"),
    "kd_lift": Range(5e-6, 3e-4, True, "leg time constants kd/kp ~1 ms to ~0.3 s: muscle-like"),
    "kp_yaw": Range(5e-4, 2e-2, True, "fore-aft compliance of the same order as the lift joints"),
    "kd_yaw": Range(5e-6, 3e-4, True, "fore-aft time constants as for the lift joints"),
    "swing_height": Range(0.3e-3, 1.5e-3, False, "foot clearance 0.3-1.5 mm, below the femur"),
    "swing_shape": Range(0.5, 2.0, False, "swing descent from gentle to steep near the AEP"),
    "com_offset_x": Range(-4e-3, 4e-3, False, "centre of mass within the thorax, +-4 mm"),
    "stand_height": Range(5.5e-3, 8.5e-3, False, "keeps every tip target within the leg's reach"),
    "foot_y": Range(9e-3, 13e-3, False, "sprawl from 4 to 8 mm beyond the body's side"),
    "stance_x_fore": Range(9e-3, 15e-3, False, "fore tips ahead of the fore coxae"),
    "stance_x_hind": Range(-15e-3, -9e-3, False, "hind tips behind the hind coxae"),
    "contact_timeconst": Range(2e-4, 2e-3, True, "stiff to moderately soft ground/tarsus"),
}


# The calibration space plus what the earlier studies found to matter or left untried (each
# range with its reason); used by the pull objective only, so the +-10% sensitivity study of
# the defaults keeps its 12 parameters.
WIDE_SPACE: dict[str, Range] = {
    **SEARCH_SPACE,
    "swing_height": Range(
        0.3e-3,
        3.0e-3,
        False,
        "foot clearance up to 3 mm (insects step over mm obstacles): "
        "a higher apex keeps landings late in the swing when a softer body sags",
    ),
    "landing_height_kept": Range(
        0.0,
        1.0,
        False,
        "0: stance from the AEP-PEP line; 1: the paper's LP -> PEP line taken "
        "literally (the landing height is kept and given up over the stance)",
    ),
    "stance_x_mid": Range(-3e-3, 3e-3, False, "middle tips within 3 mm of their coxae"),
    "friction": Range(0.7, 2.0, False, "claws and pads: from smooth to rough ground"),
}

"""Slider values -> simulation parameters, speed choices and ramps, kept pure.

The GUI hands us whatever a browser sent (a float that may be a hair outside the slider's range,
or NaN from a cleared number box); the core's `RunSpec` ranges are strict, so everything is
clamped here once, and the loop thread never has to guess whether a value is safe to apply.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim_core.contract import GROUNDS as CORE_GROUNDS
from sim_core.contract import METACHRONAL, TWO_PI, Ramp, RampParam


@dataclass(frozen=True)
class SliderRange:
    """One slider: what the browser shows and what the core accepts."""

    label: str
    lo: float
    hi: float
    step: float
    initial: float
    unit: str = ""

    def clamp(self, value: float) -> float:
        """Clamp to [lo, hi]; a non-finite value falls back to `initial`.

        Snapping to the step is left to the browser: the ramp sets values between steps.
        """
        v = float(value)
        if not math.isfinite(v):
            return self.initial
        return min(self.hi, max(self.lo, v))

    def typed(self, value: float) -> float | None:
        """The value a person means, or None while it cannot be one yet.

        A number box sends every keystroke: typing "0.62" sends 0, 0, 0.6 and 0.62. The first
        two are outside the range; they are keystrokes on the way to a value, not requests to
        clamp to 0.55 (which is what made typed betas stick at 0.55). So a value outside the
        range, or not a number at all (a lone "-"), is not applied; the browser's number box
        clamps it when the person leaves the box, and that clamped value then arrives here.
        """
        v = float(value)
        if not math.isfinite(v):
            return None
        tol = 1e-9 * max(1.0, abs(self.hi - self.lo))
        if v < self.lo - tol or v > self.hi + tol:
            return None
        return min(self.hi, max(self.lo, v))


# The paper's Fig. 5/9 range of the duty factor: metachronal above ~0.7, tripod below ~0.6.
BETA = SliderRange("β (duty factor)", 0.55, 0.80, 0.005, 0.66)
# RunSpec allows (0, 30] g; beyond 10 g the 3 g insect's legs are far outside what the paper
# studied and the viewer becomes a stress test rather than a demonstration.
BODY_MASS_G = SliderRange("body mass", 1.0, 10.0, 0.1, 3.0, "g")
# RunSpec allows (-90, 90); steeper than 30 degrees the insect slides, which says nothing new.
SLOPE_DEG = SliderRange("slope (uphill +)", -30.0, 30.0, 0.5, 0.0, "°")
# Footfall diagram: a few gait cycles (one lasts ~0.1 s at the defaults) read as a gait; 3 s is
# ~30 stance bars per leg, a barcode.
FOOTFALL_WINDOW_S = SliderRange("footfall window", 0.2, 3.0, 0.1, 0.5, "s")
D31_INIT = SliderRange("initial Δ31", 0.0, round(TWO_PI, 2), 0.01, round(METACHRONAL, 2), "rad")

# Speed choices: label -> multiplier of real time; None = as fast as the machine allows.
SPEEDS: dict[str, float | None] = {
    "0.1x": 0.1,
    "0.25x": 0.25,
    "0.5x": 0.5,
    "1x": 1.0,
    "2x": 2.0,
    "5x": 5.0,
    "max": None,
}
DEFAULT_SPEED = "1x"

# Camera modes: the follow camera moves the world under a still camera (web/scene.py).
# short labels: they are buttons side by side (web/panels.py)
CAMERA_FIXED = "fixed"
CAMERA_POSITION = "follow"
CAMERA_HEADING = "follow + turn"
CAMERA_MODES = (CAMERA_POSITION, CAMERA_HEADING, CAMERA_FIXED)
# The grounds a person may walk on (`ModelParams.ground`), by button label. The buttons say the
# ground's own name, the one the exported files, the API's `ground` field, the CLI's `--ground`
# and the result files' names say (one name: the core's; a label of our own, as the old "today's
# contact", was a second name for one thing); what each is follows in words (`GROUND_HELP`).
GROUNDS: dict[str, str] = {g: g for g in CORE_GROUNDS}
GROUND_LABEL: dict[str, str] = {v: k for k, v in GROUNDS.items()}
DEFAULT_CAMERA = CAMERA_POSITION


def camera_mode(mode: str) -> str:
    """One of CAMERA_MODES; anything else means the default ("follow")."""
    return mode if mode in CAMERA_MODES else DEFAULT_CAMERA


def beta_value(slider: float) -> float:
    return BETA.clamp(slider)


def body_mass_g_value(slider: float) -> float:
    return BODY_MASS_G.clamp(slider)


def slope_deg_value(slider: float) -> float:
    return SLOPE_DEG.clamp(slider)


def d31_init_value(slider: float) -> float:
    """Initial Delta31 in [0, 2 pi]: the slider's rounded top must not exceed RunSpec's bound."""
    return min(TWO_PI, max(0.0, D31_INIT.clamp(slider)))


def speed_label(value: float | None) -> str | None:
    """The button label of a multiple of real time (None: "max"); None if no button has it."""
    return next((k for k, v in SPEEDS.items() if v == value), None)


def speed_value(label: str) -> float | None:
    """Multiplier of real time for a dropdown label; unknown labels mean real time."""
    return SPEEDS.get(label, 1.0)


# --- the live parameters: one table, from which the sliders, the ramp's choices, the
# requests and the job bodies are made ------------------------------------------------------
@dataclass(frozen=True)
class LiveParam:
    """A RunSpec field a person sets while the insect walks (and a ramp may drive)."""

    name: RampParam  # the RunSpec field (what `Simulation.set` and a `Ramp` name it by)
    slider: SliderRange
    ramp_button: str  # the ramp's choice button
    ramp_label: str  # how the ramp's readouts and panels name it
    ramp_default: tuple[float, float]  # the sweep the ramp inputs show: (start, turn)


# The paper's Fig. 6a sweep for beta (0.70 -> 0.62 -> 0.70), and sweeps across the paper's
# Fig. 9 ranges for mass and slope.
LIVE: tuple[LiveParam, ...] = (
    LiveParam("beta", BETA, "ramp β", "β", (0.70, 0.62)),
    LiveParam("body_mass_g", BODY_MASS_G, "ramp mass", "body mass (g)", (3.0, 6.0)),
    LiveParam("slope_deg", SLOPE_DEG, "ramp slope", "slope (°)", (0.0, 20.0)),
)
LIVE_NAMES: tuple[RampParam, ...] = tuple(p.name for p in LIVE)
# derived views of the table
RAMP_SLIDERS: dict[str, SliderRange] = {p.name: p.slider for p in LIVE}
RAMP_LABELS: dict[str, str] = {p.name: p.ramp_label for p in LIVE}
RAMP_DEFAULTS: dict[str, tuple[float, float]] = {p.name: p.ramp_default for p in LIVE}
RAMP_BUTTONS: dict[str, RampParam] = {p.ramp_button: p.name for p in LIVE}
RAMP_HOLD_S = SliderRange("hold", 0.0, 600.0, 0.05, 5.0, "s")
RAMP_RAMP_S = SliderRange("ramp", 0.1, 1200.0, 0.05, 30.0, "s")


def make_ramp(param: str, start: float, turn: float, hold_s: float, ramp_s: float) -> Ramp:
    """The core's Ramp from the GUI's inputs, each clamped to what its slider allows."""
    if param not in RAMP_SLIDERS:
        raise ValueError(f"cannot ramp {param!r}; choose from {list(RAMP_SLIDERS)}")
    rng = RAMP_SLIDERS[param]
    return Ramp(
        param=param,  # type: ignore[arg-type]  # checked against RAMP_PARAMS' keys above
        start=rng.clamp(start),
        turn=rng.clamp(turn),
        hold_s=RAMP_HOLD_S.clamp(hold_s),
        ramp_s=RAMP_RAMP_S.clamp(ramp_s),
    )


def ramp_range(ramp: Ramp) -> tuple[float, float]:
    """The ramp-path panel's axis for `ramp`: its sweep with a tenth of it either side (a
    slider step when it sweeps nothing), within the ramped slider's range."""
    rng = RAMP_SLIDERS[ramp.param]
    a, b = sorted((ramp.start, ramp.turn))
    pad = 0.1 * (b - a) or rng.step
    return (max(rng.lo, a - pad), min(rng.hi, b + pad))

"""Slider values -> simulation parameters, speed choices and the beta ramp, kept pure.

The GUI hands us whatever a browser sent (a float that may be a hair outside the slider's range,
or NaN from a cleared number box); the core's `RunSpec` ranges are strict, so everything is
clamped here once, and the loop thread never has to guess whether a value is safe to apply.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

TWO_PI = 2.0 * math.pi
TRIPOD = math.pi
METACHRONAL = 2.0 * math.pi / 3.0


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
DEFAULT_CAMERA = CAMERA_POSITION


def beta_value(slider: float) -> float:
    return BETA.clamp(slider)


def body_mass_g_value(slider: float) -> float:
    return BODY_MASS_G.clamp(slider)


def slope_deg_value(slider: float) -> float:
    return SLOPE_DEG.clamp(slider)


def d31_init_value(slider: float) -> float:
    """Initial Delta31 in [0, 2 pi]: the slider's rounded top must not exceed RunSpec's bound."""
    return min(TWO_PI, max(0.0, D31_INIT.clamp(slider)))


def speed_value(label: str) -> float | None:
    """Multiplier of real time for a dropdown label; unknown labels mean real time."""
    return SPEEDS.get(label, 1.0)


@dataclass(frozen=True)
class BetaRamp:
    """A triangle wave in beta: from `start` down to `lo`, up to `hi`, back down to `start`.

    Slow enough that the gait settles at every beta (a few Delta31 samples per 0.01 of beta),
    so that the jump down (metachronal -> tripod) and the jump up happen at different betas
    and the hysteresis loop draws itself on the bifurcation panel.
    """

    start: float
    lo: float = BETA.lo
    hi: float = BETA.hi
    rate_per_s: float = 0.004  # beta per simulated second

    def __post_init__(self) -> None:
        if not self.lo < self.hi:
            raise ValueError(f"ramp needs lo < hi, got {self.lo} >= {self.hi}")
        if self.rate_per_s <= 0:
            raise ValueError(f"ramp rate must be positive, got {self.rate_per_s}")

    @property
    def duration_s(self) -> float:
        """Simulated time for the whole sweep down, up and back to the start."""
        s = min(self.hi, max(self.lo, self.start))
        return ((s - self.lo) + (self.hi - self.lo) + (self.hi - s)) / self.rate_per_s

    def beta_at(self, elapsed_s: float) -> float:
        """Beta after `elapsed_s` simulated seconds of ramp; holds `start` once finished."""
        s = min(self.hi, max(self.lo, self.start))
        d = max(0.0, elapsed_s) * self.rate_per_s
        down = s - self.lo
        if d <= down:
            return s - d
        d -= down
        span = self.hi - self.lo
        if d <= span:
            return self.lo + d
        d -= span
        return max(s, self.hi - d)

    def direction_at(self, elapsed_s: float) -> str:
        """'down', 'up' or 'done': which branch of the hysteresis loop is being drawn."""
        s = min(self.hi, max(self.lo, self.start))
        d = max(0.0, elapsed_s) * self.rate_per_s
        down = s - self.lo
        span = self.hi - self.lo
        if d < down:
            return "down"
        if d < down + span:
            return "up"
        if d < down + span + (self.hi - s):
            return "down"
        return "done"

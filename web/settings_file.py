"""The settings file the viewer exports, read back: every value checked against the range its
control takes, refused in the file's own terms.

Apart from web/export.py (which writes it, with the job bodies and the CSV files) so that each
stays a module a person reads at once; `Settings` is what both say.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any

from sim_core.contract import GROUND_DEFAULT, ModelChoice, Ramp
from web import controls
from web.paths import DEFAULT_API_URL


@dataclass(frozen=True)
class Settings:
    """The viewer's state a person set, as the export and the job bodies say it."""

    beta: float
    body_mass_g: float
    slope_deg: float
    d31_init: float  # of the last (re)start
    speed: float | None  # multiple of real time; None = as fast as possible
    time_s: float  # simulated time now
    ramp: Ramp | None  # the ramp running now, or the one set up in the ramp inputs
    ramp_running: bool
    ramp_started_at_s: float | None
    job_duration_s: float = 30.0
    api_url: str = DEFAULT_API_URL
    ground: str = GROUND_DEFAULT  # `ModelParams.ground` of the walk (the jobs' `ground` too)
    setting: str | None = None  # the named model setting of the walk (the jobs' too)
    params: dict[str, Any] = field(default_factory=dict)  # leaves on top (the jobs' `params`)

    def choice(self) -> ModelChoice:
        """The walk's model parameters, as the contract's type (checked)."""
        return ModelChoice.read({"ground": self.ground, "setting": self.setting,
                                 "params": self.params})  # fmt: skip


@dataclass(frozen=True)
class JobInputs:
    """What the panel's inputs hold for the settings beside the walk's own (read by the loop)."""

    ramp: Ramp | None  # the ramp set up in the ramp inputs (None: a box holds no number)
    duration_s: float  # a job's duration
    api_url: str


SPEED_NUMBERS = [v for v in controls.SPEEDS.values() if v is not None]


def speed_problem(speed: object) -> str:
    """The settings file's "speed" in the file's own terms: a number (a multiple of real
    time) or "max"; a button's label ("1x") is the panel's word, not the file's."""
    allowed = ", ".join(f"{v:g}" for v in SPEED_NUMBERS)
    hint = ""
    if isinstance(speed, str) and speed.endswith("x"):
        hint = f' (write {speed[:-1]}, a number, not "{speed}")'
    return f'speed: a multiple of real time ({allowed}) or "max", the file has {speed!r}{hint}'


def load_settings(data: bytes) -> Settings:
    """The settings a person exported (`settings_json`), read back: every value checked against
    the range the viewer's controls take, so a hand-edited file is refused with the field and
    its range named instead of walking at a value the sliders cannot show."""

    try:
        raw = json.loads(data)
    except (ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"not a settings file (not JSON: {exc})") from None
    if not isinstance(raw, dict):
        raise ValueError("not a settings file (a JSON object is expected)")

    def number(key: str, rng: controls.SliderRange | None = None, default: float | None = None,
               lo: float | None = None, hi: float | None = None) -> float:  # fmt: skip
        v = raw.get(key, default)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ValueError(f"{key}: a number is expected, the file has {v!r}")
        lo, hi = (rng.lo, rng.hi) if rng is not None else (lo, hi)
        if (lo is not None and v < lo) or (hi is not None and v > hi):
            raise ValueError(f"{key}: {v} is outside {lo}..{hi}")
        return float(v)

    speed = raw.get("speed", 1.0)
    if speed != "max" and (isinstance(speed, bool) or not isinstance(speed, (int, float))
                           or speed not in SPEED_NUMBERS):  # fmt: skip
        raise ValueError(speed_problem(speed))
    ground = raw.get("ground", GROUND_DEFAULT)
    if ground not in controls.GROUND_LABEL:
        raise ValueError(f"ground: one of {list(controls.GROUND_LABEL)}, the file has {ground!r}")
    model = ModelChoice.read(raw)  # setting and params, checked on the file's ground
    ramp = None
    r = raw.get("ramp")
    if r is not None:
        try:
            ramp = Ramp(r["param"], float(r["start"]), float(r["turn"]), float(r["hold_s"]),
                        float(r["ramp_s"]))  # fmt: skip
        except (KeyError, TypeError, ValueError) as exc:
            raise ValueError(
                f"ramp: param, start, turn, hold_s and ramp_s expected ({exc})"
            ) from None
        if ramp.param not in controls.RAMP_SLIDERS:
            raise ValueError(f"ramp.param: one of {list(controls.RAMP_SLIDERS)}, the file has "
                             f"{ramp.param!r}")  # fmt: skip
    return Settings(
        beta=number("beta", controls.BETA),
        body_mass_g=number("body_mass_g", controls.BODY_MASS_G),
        slope_deg=number("slope_deg", controls.SLOPE_DEG),
        d31_init=number("d31_init", lo=0.0, hi=2 * math.pi),
        speed=None if speed == "max" else float(speed),
        time_s=0.0,
        ramp=ramp,
        ramp_running=False,
        ramp_started_at_s=None,
        job_duration_s=number("job_duration_s", default=30.0, lo=1.0, hi=600.0),
        api_url=str(raw.get("api_url") or DEFAULT_API_URL),
        ground=ground,
        setting=model.setting,
        params=dict(model.params),
    )

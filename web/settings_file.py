"""The settings file the viewer exports, read back: every value checked against the range its
control takes, refused in the file's own terms.

Apart from web/export.py (which writes it, with the job bodies and the CSV files) so that each
stays a module a person reads at once; `Settings` is what both say. The run is the core's own
types: the walk's run template (`RunTemplate`: every field of RunSpec bar what a run sets for
itself) and model choice (`ModelChoice`), and the per-run fields the viewer sets (beta, the
initial Delta31, a job's duration), so a field added to RunSpec is in the file, read back and
in every job body with no edit here. The file is flat (each field by its RunSpec name at the
top level), so a file written before the template held more fields still loads: a field it
lacks is at RunSpec's default.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from pydantic import ValidationError

from sim_core.contract import GROUND_DEFAULT, ModelChoice, Ramp, RunSpec, RunTemplate
from web import controls
from web.paths import DEFAULT_API_URL


@dataclass(frozen=True)
class Settings:
    """The viewer's state a person set, as the export and the job bodies say it."""

    run: RunTemplate  # the walk's spec bar the per-run fields, live mass and slope included
    beta: float  # now (a per-run field: the template leaves it out)
    d31_init: float  # of the last (re)start
    speed: float | None  # multiple of real time; None = as fast as possible
    time_s: float  # simulated time now
    ramp: Ramp | None  # the ramp running now, or the one set up in the ramp inputs
    ramp_running: bool
    ramp_started_at_s: float | None
    job_duration_s: float = 30.0
    api_url: str = DEFAULT_API_URL
    # the walk's model parameters: ground, named setting, leaves (the jobs' too)
    model: ModelChoice = field(default_factory=ModelChoice)

    def spec(self, **override: Any) -> RunSpec:
        """The contract's spec of the walk (its template, beta and the last start), checked by
        the core's own rules; `override` replaces what a ramp or a job sets."""
        return self.run.spec(**({"beta": self.beta, "d31_init": self.d31_init} | override))

    def choice(self) -> ModelChoice:
        """The walk's model parameters, as the contract's type (checked)."""
        return self.model

    @property
    def body_mass_g(self) -> float:
        return self.spec().body_mass_g

    @property
    def slope_deg(self) -> float:
        return self.spec().slope_deg

    @property
    def ground(self) -> str:
        return self.model.ground


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


def _words(exc: ValidationError) -> str:
    """A validation error in one line, each refused field by name ("dt_s: Input should...")."""
    words = [f"{'.'.join(map(str, e['loc'])) or 'run'}: {e['msg']}" for e in exc.errors()]
    return "; ".join(words).replace("Value error, ", "")


def read_run(raw: Mapping[str, Any]) -> RunTemplate:
    """The run template among the file's fields (RunSpec's names; one it lacks at RunSpec's
    default), strict as a job (no "3" for 3, no "yes" for true); a ValueError naming each
    refused field."""
    try:
        fields = {k: raw[k] for k in RunTemplate.model_fields if k in raw}
        return RunTemplate.model_validate(fields, strict=True)
    except ValidationError as exc:
        raise ValueError(_words(exc)) from None


def read_ramp(r: Any) -> Ramp | None:
    """The file's ramp (None: none set up), of a parameter a slider drives."""
    if r is None:
        return None
    try:
        ramp = Ramp(r["param"], float(r["start"]), float(r["turn"]), float(r["hold_s"]),
                    float(r["ramp_s"]))  # fmt: skip
    except (KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"ramp: param, start, turn, hold_s and ramp_s expected ({exc})") from None
    if ramp.param not in controls.RAMP_SLIDERS:
        raise ValueError(f"ramp.param: one of {list(controls.RAMP_SLIDERS)}, the file has "
                         f"{ramp.param!r}")  # fmt: skip
    return ramp


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
    ramp = read_ramp(raw.get("ramp"))
    # the live parameters in their sliders' ranges (RunSpec's own are wider)
    live = {p.name: number(p.name, p.slider) for p in controls.LIVE}
    d31_init = number("d31_init", lo=0.0, hi=2 * math.pi)
    settings = Settings(
        run=read_run(raw),
        beta=live["beta"],
        d31_init=d31_init,
        speed=None if speed == "max" else float(speed),
        time_s=0.0,
        ramp=ramp,
        ramp_running=False,
        ramp_started_at_s=None,
        job_duration_s=number("job_duration_s", default=30.0, lo=1.0, hi=600.0),
        api_url=str(raw.get("api_url") or DEFAULT_API_URL),
        model=model,
    )
    try:
        settings.spec()  # RunSpec's cross-field rules (the numerics), each refusal by name
    except ValidationError as exc:
        raise ValueError(_words(exc)) from None
    return settings

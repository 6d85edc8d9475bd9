"""What the page exports and what it offers to submit: files and REST job bodies, kept pure.

The loop thread builds each file from the simulation's record when a browser asks (a download button
queues an `Export` request) and hands the bytes to that browser (viser's
`ClientHandle.send_file_download`). The REST bodies are what `POST /v1/jobs` takes
(docs/API.md): a `run` job at the current settings and, when a ramp is set up, the
`hysteresis` job that runs the same ramp (`Ramp`'s fields are the job's).
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

from sim_core.contract import LEG_NAMES, Ramp, RunSpec
from web import controls
from web.paths import DEFAULT_API_URL
from web.record import D31Event, Interval

EXPORTS = ("d31", "footfall", "ramp", "settings")
D31_COLUMNS = ("time_s", "d31_rad", "beta", "body_mass_g", "slope_deg", "ramp")


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
    ground: str = "constraint"  # `ModelParams.ground` of the walk (the jobs' `ground` too)


def _csv(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> bytes:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for row in rows:
        w.writerow(["" if isinstance(v, float) and not math.isfinite(v) else v for v in row])
    return buf.getvalue().encode()


def _event_row(e: D31Event) -> tuple[Any, ...]:
    """One touchdown: times and angles to 1 us / 1 urad, the parameters to 1e-6 of their
    unit (a ramp's value is continuous: 3.0149999999999864 g is written 3.015), and the ramp
    as 'beta up' (its parameter and phase) while one ran."""
    ramp = f"{e.at.ramp_param} {e.at.ramp}".strip() if e.at.ramp else ""
    return (
        round(e.time_s, 6),
        round(e.d31, 6),
        round(e.at.beta, 6),
        round(e.at.body_mass_g, 6),
        round(e.at.slope_deg, 6),
        ramp,
    )


def d31_csv(events: Iterable[D31Event]) -> bytes:
    """Delta31 at every leg-1 touchdown kept (the whole run), with the parameters then."""
    return _csv(D31_COLUMNS, (_event_row(e) for e in events))


def footfall_csv(intervals: Sequence[Sequence[Interval]]) -> bytes:
    """Stance intervals, per leg in paper order (`record.stance_intervals`), as rows (leg
    R1..L3, start, end in s) in order of their start."""
    rows = sorted((a, leg, b) for leg, legs in enumerate(intervals) for a, b in legs)
    return _csv(
        ("leg", "start_s", "end_s"),
        ((LEG_NAMES[leg], round(a, 6), round(b, 6)) for a, leg, b in rows),
    )


def ramp_csv(path: Iterable[D31Event], ramp: Ramp | None, started_at_s: float | None) -> bytes:
    """The ramp's path: each touchdown during the ramp with the scheduled value of the ramped
    parameter (`Ramp.value` at that time) next to the parameters in force."""
    rows = []
    for e in path:
        scheduled = (
            ramp.value(e.time_s - started_at_s)
            if ramp is not None and started_at_s is not None
            else math.nan
        )
        rows.append((*_event_row(e), scheduled))
    return _csv((*D31_COLUMNS, "scheduled"), rows)


# The run fields the viewer sets, as RunSpec (the contract) names them; the job bodies carry
# these from a validated RunSpec, so a body holds what the core itself would run.
HELD_FIELDS = controls.LIVE_NAMES


def _fields(spec: RunSpec, names: Sequence[str]) -> dict[str, Any]:
    """RunSpec fields to 1e-6 of their unit (a ramp's value is continuous: 3.015, not
    3.0149999999999864)."""
    return {n: round(getattr(spec, n), 6) for n in names}


def run_spec(s: Settings, **override: float) -> RunSpec:
    """The contract's spec of the current walk (beta, mass, slope, the last start), checked by
    the core's own rules; `override` replaces what a ramp sets."""
    return RunSpec(
        **({n: getattr(s, n) for n in HELD_FIELDS} | {"d31_init": s.d31_init} | override)
    )


def run_job(s: Settings) -> dict[str, Any]:
    """A `run` job at the current beta, mass and slope from the last initial Delta31, with its
    time series (the viewer draws the job's Delta31 beside the live walk's)."""
    spec = run_spec(s, duration_s=s.job_duration_s)
    return {
        "kind": "run",
        **_fields(spec, (*HELD_FIELDS, "duration_s")),
        "d31_init": [round(spec.d31_init, 6)],  # the run job takes a list of starts
        "ground": s.ground,
        "include_series": True,
    }


def hysteresis_job(s: Settings, ramp: Ramp) -> dict[str, Any]:
    """The same ramp as a `hysteresis` job (the contract's `Ramp`'s fields are the job's): the
    held parameters are the current ones, the ramped one starts at the ramp's start."""
    spec = run_spec(s, **{ramp.param: ramp.start})
    return {
        "kind": "hysteresis",
        "parameter": ramp.param,
        "start": ramp.start,
        "turn": ramp.turn,
        "hold_s": ramp.hold_s,
        "ramp_s": ramp.ramp_s,
        **_fields(spec, (*HELD_FIELDS, "d31_init")),
        "ground": s.ground,
    }


def jobs(s: Settings) -> dict[str, dict[str, Any]]:
    out = {"run": run_job(s)}
    if s.ramp is not None:
        out["hysteresis"] = hysteresis_job(s, s.ramp)
    return out


def curl(api_url: str, body: dict[str, Any]) -> str:
    """The command line that submits `body` (the API may ask for a bearer token: docs/API.md)."""
    data = json.dumps(body, separators=(", ", ": "))
    return (
        f"curl -s -X POST {api_url.rstrip('/')}/v1/jobs "
        f"-H 'Content-Type: application/json' -d '{data}'"
    )


def settings_json(s: Settings) -> bytes:
    """The settings in force, as a person reads them: "speed" is a multiple of real time or
    "max" (as fast as the machine steps), never null."""
    out = asdict(s)
    out["speed"] = "max" if s.speed is None else s.speed
    out["ramp"] = None if s.ramp is None else asdict(s.ramp)
    out["jobs"] = jobs(s)
    out["jobs_url"] = f"{s.api_url.rstrip('/')}/v1/jobs"
    return json.dumps(out, indent=2).encode()


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
                           or speed not in [s for s in controls.SPEEDS.values() if s]):  # fmt: skip
        raise ValueError(f"speed: one of {list(controls.SPEEDS)} is expected, the file has "
                         f"{speed!r}")  # fmt: skip
    ground = raw.get("ground", "constraint")
    if ground not in controls.GROUND_LABEL:
        raise ValueError(f"ground: one of {list(controls.GROUND_LABEL)}, the file has {ground!r}")
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
    )

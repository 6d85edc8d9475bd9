"""What the page exports and what it offers to submit: files and REST job bodies, kept pure.

The loop thread builds each file from the simulation's record when a browser asks (a download button
queues an `Export` request) and hands the bytes to that browser (viser's
`ClientHandle.send_file_download`). The REST bodies are what `POST /v1/jobs` takes
(docs/API.md): a `run` job at the current settings and, when a ramp is set up, the
`hysteresis` job that runs the same ramp (the job holds the contract's `Ramp`, as `ramp`).
"""

from __future__ import annotations

import bisect
import csv
import dataclasses
import html
import io
import json
import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict
from typing import Any

from sim_core.contract import (
    LEG_NAMES,
    EventConditions,
    ModelChoice,
    Ramp,
    RunSpec,
    RunTemplate,
    provenance,
)
from web.record import D31Event, Interval
from web.settings_file import Settings, load_settings

# `Settings` and `load_settings` live in web/settings_file.py (the file read back); the
# export names them too, as the writer of that file
__all__ = ["D31_COLUMNS", "EXPORTS", "PROVENANCE_COLUMNS", "Settings", "d31_csv", "footfall_csv",
           "job_html", "jobs", "load_settings", "made_by", "ramp_csv", "run_job",
           "settings_json"]  # fmt: skip
EXPORTS = ("d31", "footfall", "ramp", "settings")
CONDITION_COLUMNS = ("beta", "body_mass_g", "slope_deg")
# What made the numbers, on every row (the core's `provenance`: the physics' version, the
# parameter hash the result cache uses, the ground and the physics step; and the model
# parameters off their defaults as JSON, `ViewerState.provenance`): columns, not a
# commented header, so that every CSV reader keeps them with each row.
PROVENANCE_COLUMNS = ("ground", "params", "dt_s", "physics_version", "params_hash")
D31_COLUMNS = ("time_s", "d31_rad", *CONDITION_COLUMNS, "ramp", *PROVENANCE_COLUMNS)
Provenance = dict[str, Any]  # `made_by`: what made the walk's numbers


def made_by(model: ModelChoice) -> Provenance:
    """What makes a walk's numbers, for every export: the core's `provenance` (physics
    version, the parameter hash the cache uses, ground, dt) and the model parameters off their
    defaults, as JSON by leaf name (`ModelChoice.changed`)."""
    changed = json.dumps(model.changed(), sort_keys=True)
    return provenance(model.model_params()) | {"params": changed}


def _csv(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> bytes:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for row in rows:
        w.writerow(["" if isinstance(v, float) and not math.isfinite(v) else v for v in row])
    return buf.getvalue().encode()


def _stamp(made: Provenance) -> tuple[Any, ...]:
    return tuple(made[c] for c in PROVENANCE_COLUMNS)


def _at(at: EventConditions) -> tuple[float, ...]:
    """The parameters in force to 1e-6 of their unit (a ramp's value is continuous:
    3.0149999999999864 g is written 3.015)."""
    return tuple(round(getattr(at, c), 6) for c in CONDITION_COLUMNS)


def _event_row(e: D31Event, made: Provenance) -> tuple[Any, ...]:
    """One touchdown: times and angles to 1 us / 1 urad, the parameters then, the ramp as
    'beta up' (its parameter and phase) while one ran, and what made the numbers."""
    ramp = f"{e.at.ramp_param} {e.at.ramp}".strip() if e.at.ramp else ""
    return (round(e.time_s, 6), round(e.d31, 6), *_at(e.at), ramp, *_stamp(made))


def d31_csv(events: Iterable[D31Event], *, made: Provenance) -> bytes:
    """Delta31 at every leg-1 touchdown kept (the whole run), with the parameters then."""
    return _csv(D31_COLUMNS, (_event_row(e, made) for e in events))


def footfall_csv(
    intervals: Sequence[Sequence[Interval]],
    events: Sequence[D31Event],
    now: EventConditions,
    *,
    made: Provenance,
) -> bytes:
    """Stance intervals, per leg in paper order (`record.stance_intervals`), as rows (leg
    R1..L3, start, end in s) in order of their start, each with the parameters in force at
    the latest leg-1 touchdown up to its start (the core records them at touchdowns; before
    the first one, the first one's; with none yet, `now`'s)."""
    times = [e.time_s for e in events]

    def at(t: float) -> EventConditions:
        if not events:
            return now
        return events[max(0, bisect.bisect_right(times, t) - 1)].at

    rows = sorted((a, leg, b) for leg, legs in enumerate(intervals) for a, b in legs)
    return _csv(
        ("leg", "start_s", "end_s", *CONDITION_COLUMNS, *PROVENANCE_COLUMNS),
        ((LEG_NAMES[leg], round(a, 6), round(b, 6), *_at(at(a)), *_stamp(made))
         for a, leg, b in rows),
    )  # fmt: skip


def ramp_csv(
    path: Iterable[D31Event], ramp: Ramp | None, started_at_s: float | None, *, made: Provenance
) -> bytes:
    """The ramp's path: each touchdown during the ramp with the scheduled value of the ramped
    parameter (`Ramp.value` at that time) next to the parameters in force."""
    rows = []
    for e in path:
        scheduled = (
            ramp.value(e.time_s - started_at_s)
            if ramp is not None and started_at_s is not None
            else math.nan
        )
        rows.append((*_event_row(e, made), scheduled))
    return _csv((*D31_COLUMNS, "scheduled"), rows)


def _tidy(v: Any) -> Any:
    """A number to 1e-6 of its unit (a ramp's value is continuous: 3.015, not
    3.0149999999999864); anything else as is."""
    return round(v, 6) if isinstance(v, float) else v


def _fields(spec: RunSpec, per_run: Sequence[str]) -> dict[str, Any]:
    """A job's run fields from a validated RunSpec: every field of the run template (the
    server composes every job from the same `RunTemplate`, so no field is left behind) and
    the per-run ones the job takes, so a body holds what the core itself would run."""
    return {n: _tidy(getattr(spec, n)) for n in (*RunTemplate.model_fields, *per_run)}


def run_job(s: Settings) -> dict[str, Any]:
    """A `run` job at the current settings from the last initial Delta31, with its time series
    (the viewer draws the job's Delta31 beside the live walk's)."""
    spec = s.spec(duration_s=s.job_duration_s)
    return {
        "kind": "run",
        **_fields(spec, ("beta", "duration_s")),
        "d31_init": [round(spec.d31_init, 6)],  # the run job takes a list of starts
        **s.model.body(),  # ground, and setting and params where not the defaults
        "include_series": True,
    }


def hysteresis_job(s: Settings, ramp: Ramp) -> dict[str, Any]:
    """The same ramp as a `hysteresis` job (the job holds the contract's `Ramp`, as `ramp`):
    the held parameters are the current ones, the ramped one starts at the ramp's start."""
    spec = s.spec(**{ramp.param: ramp.start})
    return {
        "kind": "hysteresis",
        "ramp": dataclasses.asdict(ramp),
        **_fields(spec, ("beta", "d31_init")),
        **s.model.body(),
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


def job_html(s: Settings) -> str:
    """The current settings as REST job bodies to copy, with the curl line and the URL (the
    panel's "Submit as a job" folder shows it)."""
    url = s.api_url.rstrip("/")
    parts = [
        f'<div data-job-url="{html.escape(url)}/v1/jobs" style="font-size:0.8em">',
        f"<b>POST</b> <code>{html.escape(url)}/v1/jobs</code> "
        f'(<a href="{html.escape(url)}/docs" target="_blank">API docs</a>)',
    ]
    for kind, body in jobs(s).items():
        text = json.dumps(body, indent=1)
        parts.append(
            f"<div>a <b>{kind}</b> job{' (the ramp set up above)' if kind == 'hysteresis' else ''}:"
            f'</div><pre data-job="{kind}" style="white-space:pre-wrap;user-select:all;'
            f'margin:2px 0;padding:3px;background:#f4f4f4">{html.escape(text)}</pre>'
            f'<pre style="white-space:pre-wrap;user-select:all;margin:2px 0;font-size:0.9em">'
            f"{html.escape(curl(url, body))}</pre>"
        )
    parts.append("</div>")
    return "".join(parts)


def settings_json(s: Settings, *, made: Provenance) -> bytes:
    """The settings in force, as a person reads them: "speed" is a multiple of real time or
    "max" (as fast as the machine steps), never null; "provenance": what made the walk's
    numbers (read back by nobody: a loaded file walks on today's physics)."""
    # flat: each run field by its RunSpec name, as a job body names it (`load_settings`)
    out = s.run.model_dump(mode="json") | s.model.model_dump(mode="json")  # + ground, params
    out |= {f.name: getattr(s, f.name) for f in dataclasses.fields(s)
            if f.name not in ("run", "model")}  # fmt: skip
    out["provenance"] = dict(made)
    out["speed"] = "max" if s.speed is None else s.speed
    out["ramp"] = None if s.ramp is None else asdict(s.ramp)
    out["jobs"] = jobs(s)
    out["jobs_url"] = f"{s.api_url.rstrip('/')}/v1/jobs"
    return json.dumps(out, indent=2).encode()

"""A finished job replayed in the viewer's panels: its result converted into what the live
panels draw, kept pure.

The panels that draw the live walk (Delta31 history, footfall, ramp path) draw a job's run with
the same functions (web/d31_svg.py, web/footfall_svg.py, web/bifurcation_svg.py), so a job and
the walk read alike; each replayed panel carries a line above it naming the job and its
conditions, so nobody takes it for the live walk. The shapes read are the API's documented
results (docs/API.md): a `run` job with `include_series` keeps each run's record
(`runs[k]`: `d31_times_s`, `d31`, `times_s`, `stance`, `gait`) and the `series` tables; a
`hysteresis` job keeps one row per leg-1 touchdown (`time_s`, `value`, `d31`).
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim_core.contract import EventConditions, Ramp
from web import controls
from web.bifurcation_svg import ramp_path_svg
from web.d31_svg import d31_svg
from web.footfall_svg import footfall_svg
from web.record import D31Event, Interval, Mark, change_label, stance_intervals
from web.style import JOB_COLOUR

REPLAYABLE = ("run", "hysteresis")  # the kinds whose runs the live panels can draw
PANELS = ("d31", "footfall", "ramp")  # the panels a replay may fill


@dataclass(frozen=True)
class Replay:
    """A done job's first run as the live panels draw it."""

    job_id: str
    kind: str
    conditions: str  # "β 0.620, 3.00 g, slope 0.0°, ground constraint"
    d31: tuple[tuple[float, float], ...]  # (time_s, Delta31) at each leg-1 touchdown
    gait: str  # what the job says of its run's gait ("" when it says nothing)
    footfall: tuple[tuple[Interval, ...], ...] = ()  # per leg (paper order); run jobs only
    ramp: Ramp | None = None  # hysteresis jobs: the schedule the job ran
    path: tuple[D31Event, ...] = ()  # hysteresis jobs: each touchdown with what was in force

    @property
    def end_s(self) -> float:
        """The run's last simulated second the replay has."""
        ends = [t for t, _ in self.d31[-1:]] + [b for leg in self.footfall for _, b in leg[-1:]]
        return max(ends, default=0.0)

    @property
    def panels(self) -> tuple[str, ...]:
        """The live panels this replay fills (the others keep the live walk)."""
        has = (bool(self.d31), bool(self.footfall), self.ramp is not None)
        return tuple(p for p, filled in zip(PANELS, has, strict=True) if filled)

    @property
    def marks(self) -> list[Mark]:
        """The ramp's phases on the job's Delta31 history, in the live history's words."""
        out = []
        for before, now in zip(self.path, self.path[1:], strict=False):
            label = change_label(before.at, now.at)
            if label:
                out.append(Mark(now.time_s, label, by_person=False))
        return out


def first_run_d31(result: dict[str, Any]) -> tuple[tuple[float, float], ...]:
    """(time_s, Delta31) of a run job's first run from its stored result (`GET .../result`),
    or () when the job kept no series or is of another kind."""
    rows = result.get("result", {}).get("series", {}).get("d31", [])
    return tuple((float(r["time_s"]), float(r["d31"])) for r in rows if r.get("run") == 0)


def conditions_words(spec: dict[str, Any]) -> str:
    """What the job's walk was held at, from its stored spec."""
    formats = (("beta", "β {:.3f}"), ("body_mass_g", "{:.2f} g"),
               ("slope_deg", "slope {:.1f}°"), ("ground", "ground {}"))  # fmt: skip
    return ", ".join(fmt.format(spec[k]) for k, fmt in formats if spec.get(k) is not None)


def replay_of(
    kind: str, job_id: str, spec: dict[str, Any], result: dict[str, Any]
) -> Replay | None:
    """The replay of a done job from its spec (`GET /v1/jobs/{id}`: `spec`) and stored result
    (`GET .../result`), or None when its kind or what it kept gives nothing to draw (a run
    job without `include_series` kept no times)."""
    body = result.get("result", {})
    if kind == "run":
        return _run_replay(job_id, spec, result, body)
    if kind == "hysteresis":
        return _hysteresis_replay(job_id, spec, body)
    return None


def _run_replay(
    job_id: str, spec: dict[str, Any], result: dict[str, Any], body: dict[str, Any]
) -> Replay | None:
    d31 = first_run_d31(result)
    runs = body.get("runs") or [{}]
    first = runs[0] if isinstance(runs[0], dict) else {}
    times, stance = first.get("times_s") or [], first.get("stance") or []
    footfall: tuple[tuple[Interval, ...], ...] = ()
    if len(times) >= 2 and len(stance) == len(times):
        legs = stance_intervals(np.asarray(times, float), np.asarray(stance, bool))
        footfall = tuple(tuple(leg) for leg in legs)
    if not d31 and not footfall:
        return None
    gait = str(first.get("gait") or "")
    return Replay(job_id, "run", conditions_words(spec), d31, gait, footfall)


def _hysteresis_replay(job_id: str, spec: dict[str, Any], body: dict[str, Any]) -> Replay | None:
    rows = body.get("records") or []
    # the job's `ramp` (the contract's `Ramp`); a job stored before it was one kept it flat
    r = spec.get("ramp") or {**spec, "param": spec.get("parameter")}
    try:
        ramp = Ramp(
            r["param"], float(r["start"]), float(r["turn"]), float(r["hold_s"]),
            float(r["ramp_s"]),
        )  # fmt: skip
    except (KeyError, TypeError, ValueError):
        return None
    if not rows or ramp.param not in controls.RAMP_SLIDERS:
        return None
    held = {n: float(spec.get(n, controls.RAMP_SLIDERS[n].initial)) for n in controls.LIVE_NAMES}
    ground = str(spec.get("ground") or "")
    path = []
    for r in rows:
        t = float(r["time_s"])
        at = held | {ramp.param: float(r["value"])}
        phase = ramp.phase(t)  # a touchdown at the schedule's very end is still its hold
        phase = "hold" if phase == "done" else phase
        conditions = EventConditions(
            at["beta"], at["body_mass_g"], at["slope_deg"], ground, phase, ramp.param
        )
        path.append(D31Event(t, float(r["d31"]), conditions))
    d31 = tuple((e.time_s, e.d31) for e in path)
    return Replay(job_id, "hysteresis", conditions_words(spec), d31, "", (), ramp, tuple(path))


def header_html(replay: Replay, what: str) -> str:
    """The line above a replayed panel: whose run it is, under what, and that it is not live."""
    return (
        f'<div data-replay="{html.escape(replay.job_id)}" style="font-size:0.8em;'
        f'color:{JOB_COLOUR};font-weight:bold;overflow-wrap:anywhere">'
        f"▶ replay of {replay.kind} job {html.escape(replay.job_id[:8])}: {what} "
        f"({html.escape(replay.conditions)}) — not the live walk</div>"
    )


def replay_panel(replay: Replay, panel: str, window_s: float) -> str:
    """One live panel's content for `replay`: the header line and the panel's own drawing
    (`panel` one of PANELS; the footfall over the run's last `window_s`, as the live one)."""
    if panel == "d31":
        gait = replay.gait or ("a ramp: see the ramp path" if replay.ramp else "–")
        svg = d31_svg(replay.d31, replay.end_s, None, gait, replay.marks)
        return header_html(replay, "Δ31 at each leg-1 touchdown") + svg
    if panel == "footfall":
        bars: Sequence[Sequence[Interval]] = replay.footfall
        svg = footfall_svg(bars, replay.end_s, window_s)
        return header_html(replay, f"its footfall, the run's last {window_s:g} s") + svg
    if panel == "ramp" and replay.ramp is not None:
        r = replay.ramp
        svg = ramp_path_svg(
            list(replay.path), r.param, controls.RAMP_LABELS[r.param], controls.ramp_range(r)
        )
        return header_html(replay, "its ramp path") + svg
    raise ValueError(f"replay {replay.job_id} has no {panel!r} panel; it has {replay.panels}")

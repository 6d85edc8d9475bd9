"""The job list's pure parts: its states in words, a done job's result as the panels' replay,
the exports' provenance columns, and the core's one ground name in the viewer."""

from __future__ import annotations

import csv
import io
import json
import urllib.error
from email.message import Message
from typing import Any

import pytest

from sim_core.contract import (
    GROUND_HELP,
    GROUNDS,
    PHYSICS_VERSION,
    EventConditions,
    ModelChoice,
    ModelParams,
    RunTemplate,
    params_hash,
    provenance,
)
from web import controls, export
from web.job_replay import Replay, replay_of, replay_panel
from web.job_words import job_row_html, problem, state_words
from web.jobs import JobView, JobWatcher
from web.record import D31Event


def _http(code: int, detail: Any) -> urllib.error.HTTPError:
    body = io.BytesIO(json.dumps({"detail": detail}).encode())
    return urllib.error.HTTPError("http://h/v1/jobs", code, "reason", Message(), body)


def test_each_failure_has_its_own_state_in_words_and_no_exception_names() -> None:
    api = "http://127.0.0.1:9"
    refused = urllib.error.URLError(ConnectionRefusedError(111, "Connection refused"))
    cases = {
        "unreachable": problem(refused, api),
        "not found": problem(_http(404, "job abc not found"), api),
        "refused": problem(_http(422, [{"loc": ["body", "beta"], "msg": "too big"}]), api),
        "API error": problem(_http(500, "boom"), api),
    }
    for state, (got, message) in cases.items():
        assert got == state
        assert "Error" not in message and "URLError" not in message  # no Python names
    assert cases["unreachable"][1].startswith(f"no API answers at {api} (connection refused)")
    assert "make run" in cases["unreachable"][1]
    assert cases["not found"][1] == "the API has no such job (HTTP 404: job abc not found)"
    assert cases["refused"][1] == "the API refused it (HTTP 422): beta: too big"
    assert problem(TimeoutError(), api)[0] == "unreachable"


def test_a_running_job_says_how_far_it_is_and_its_row_offers_what_it_can() -> None:
    running = JobView(id="0123456789", kind="run", status="running", progress=0.4, eta_s=12.0,
                      url="http://h/v1/jobs/0123456789", key=3)  # fmt: skip
    assert state_words(running) == "running 40%, about 12 s left"
    assert running.cancellable and not running.finished
    row = job_row_html(running, replaying=False)
    assert 'data-job-row="3"' in row and ">01234567</a>" in row and "running 40%" in row
    for status in ("done", "failed", "cancelled", "not found", "refused", "unreachable"):
        v = JobView(id="x", status=status, url="http://h/v1/jobs/x")
        assert v.finished and not v.cancellable
    assert JobView(status="queued").cancellable is False  # no id yet: nothing to cancel


def test_the_list_keeps_the_newest_jobs_one_row_per_job() -> None:
    w = JobWatcher(poll_s=0.01, timeout_s=0.5)
    keys = [w.open("http://127.0.0.1:9", f"job-{k}") for k in range(10)]
    views = w.views
    assert len(views) == 8 and views[0].key == keys[-1] and w.view.key == keys[-1]
    assert w.get(keys[0]) is None  # the oldest left the list: no longer followed
    again = w.open("http://127.0.0.1:9", "job-9")
    assert [v.id for v in w.views].count("job-9") == 1 and w.views[0].key == again
    assert not w.cancel(again)  # not a queued or running job of the list


RUN_SPEC = {"beta": 0.62, "body_mass_g": 3.0, "slope_deg": 0.0, "ground": "penalty"}


def _run_result() -> dict[str, Any]:
    times = [0.01 * k for k in range(100)]
    stance = [[k % 20 < 12, k % 20 >= 10, True, False, k < 50, False] for k in range(100)]
    d31 = [(0.1 * k + 0.05, 2.0 + 0.1 * k) for k in range(10)]
    rows = [{"run": 0, "time_s": t, "d31": d} for t, d in d31]
    rows += [{"run": 1, "time_s": 0.5, "d31": 9.0}]  # another run: not the first
    run = {"times_s": times, "stance": stance, "gait": "tripod"}
    return {"result": {"runs": [run], "series": {"d31": rows}}}


def test_a_run_job_replays_its_first_runs_delta31_and_footfall() -> None:
    r = replay_of("run", "abcdef0123", RUN_SPEC, _run_result())
    assert r is not None and r.panels == ("d31", "footfall")
    assert len(r.d31) == 10 and r.d31[0] == (0.05, 2.0) and r.gait == "tripod"
    assert r.footfall[0][0] == (0.0, 0.12) and r.footfall[3] == ()  # R1's first stance; L2 none
    assert r.footfall[2] == ((0.0, 0.99),) and r.end_s == pytest.approx(0.99)
    assert r.conditions == "β 0.620, 3.00 g, slope 0.0°, ground penalty"
    d31 = replay_panel(r, "d31", 0.5)
    assert 'data-replay="abcdef0123"' in d31 and "not the live walk" in d31
    assert 'data-n-events="10"' in d31 and "gait: tripod" in d31
    foot = replay_panel(r, "footfall", 0.5)
    assert "the run's last 0.5 s" in foot and 'data-plot="footfall"' in foot
    with pytest.raises(ValueError, match="no 'ramp' panel"):
        replay_panel(r, "ramp", 0.5)
    # a run job that kept no series has nothing to replay; nor has another kind
    assert replay_of("run", "x", RUN_SPEC, {"result": {"runs": [{"gait": "tripod"}]}}) is None
    assert replay_of("surface", "x", {}, {"result": {}}) is None


@pytest.mark.parametrize("shape", ["ramp", "flat (stored before issue 53)"])
def test_a_hysteresis_job_replays_its_ramp_path_with_its_phases(shape: str) -> None:
    held = {"beta": 0.66, "body_mass_g": 4.0, "slope_deg": 0.0, "ground": "constraint"}
    schedule = {"start": 0.70, "turn": 0.62, "hold_s": 1.0, "ramp_s": 2.0}
    spec = (held | {"ramp": {"param": "beta", **schedule}} if shape == "ramp"
            else held | {"parameter": "beta", **schedule})  # fmt: skip
    times = [0.25 * k for k in range(25)]  # 0 .. 6 s: hold, down, up, hold
    ramp = controls.make_ramp("beta", 0.70, 0.62, 1.0, 2.0)
    records = [{"time_s": t, "leg": "first", "value": ramp.value(t), "d31": 1.9} for t in times]
    r = replay_of("hysteresis", "feed", spec, {"result": {"records": records}})
    assert isinstance(r, Replay) and r.panels == ("d31", "ramp") and r.ramp == ramp
    phases = [e.at.ramp for e in r.path]
    assert phases[0] == "hold" and "down" in phases and "up" in phases and phases[-1] == "hold"
    assert all(e.at.body_mass_g == 4.0 and e.at.beta == ramp.value(e.time_s) for e in r.path)
    assert [m.label for m in r.marks] == ["ramp β down", "ramp β up", "ramp β hold"]
    path = replay_panel(r, "ramp", 0.5)
    assert 'data-plot="ramp-path"' in path and 'data-direction="down"' in path
    assert "its ramp path" in path and "not the live walk" in path
    assert replay_of("hysteresis", "x", {"parameter": "beta"}, {"result": {"records": []}}) is None


def test_every_export_names_the_physics_that_made_it() -> None:
    made = export.made_by(ModelChoice(ground="penalty", params={"kp_lift": 1e-3}))
    leafy = ModelParams.of(ground="penalty", kp_lift=1e-3)
    assert made == {"physics_version": PHYSICS_VERSION, "ground": "penalty",
                    "params_hash": params_hash(leafy), "params": '{"kp_lift": 0.001}',
                    "dt_s": leafy.numerics.dt}  # fmt: skip
    assert made["params_hash"] != provenance(None)["params_hash"]
    at = [EventConditions(0.62, 3.0 + k, 0.0, "penalty") for k in range(3)]
    events = [D31Event(1.0 * k, 2.0, at[k]) for k in range(3)]
    for data in (export.d31_csv(events, made=made),
                 export.ramp_csv(events, None, None, made=made),
                 export.footfall_csv([[(0.5, 0.7), (1.5, 1.6)]] + [[]] * 5, events, at[0],
                                     made=made)):  # fmt: skip
        rows = list(csv.DictReader(io.StringIO(data.decode())))
        assert rows and all(
            r["physics_version"] == PHYSICS_VERSION and r["params_hash"] == made["params_hash"]
            and r["ground"] == "penalty" and float(r["dt_s"]) == made["dt_s"]
            and json.loads(r["params"]) == {"kp_lift": 1e-3}
            for r in rows
        )  # fmt: skip
    foot = list(csv.DictReader(io.StringIO(export.footfall_csv(
        [[(0.5, 0.7), (1.5, 1.6)]] + [[]] * 5, events, at[0], made=made).decode())))  # fmt: skip
    # each stance with the mass in force at the latest touchdown before it began
    assert [r["body_mass_g"] for r in foot] == ["3.0", "4.0"]
    s = export.Settings(RunTemplate(), 0.62, 2.09, 1.0, 0.0, None, False, None,
                        model=ModelChoice(ground="penalty"))  # fmt: skip
    assert json.loads(export.settings_json(s, made=made))["provenance"] == made


def test_the_ground_has_one_name_the_cores() -> None:
    assert list(controls.GROUNDS) == list(GROUNDS) == list(controls.GROUND_LABEL.values())
    assert all(f"{g}:" in GROUND_HELP for g in GROUNDS)

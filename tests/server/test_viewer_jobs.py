"""The viewer's job client (web/jobs.py) against the real service: jobs submitted from the
viewer are listed and followed to their end with their figure; an existing job opens by its
id; a queued or running job is cancelled from its row; a done run or hysteresis job replays in
the viewer's panels (labelled as the job's) and the live walk comes back; a refused body, an
unknown id and an absent API are each said in their own words, never raised into the loop."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

from api_harness import SHORT, free_port, submit, wait_for

from web.job_words import job_status_html
from web.jobs import JobView, JobWatcher

PNG = b"\x89PNG\r\n\x1a\n"
RAMP = {"kind": "hysteresis", "ramp": {"param": "beta", "start": 0.70, "turn": 0.64,
        "hold_s": 0.3, "ramp_s": 0.6}, "beta": 0.66, "d31_init": 1.9}  # fmt: skip


def _finished(w: JobWatcher, key: int) -> JobView | None:
    v = w.get(key)
    return v if v is not None and v.finished and (v.status != "done" or v.figure_png) else None


def test_jobs_submitted_from_the_viewer_are_listed_and_followed_to_their_figure(
    make_server: Any, tmp_path: Path
) -> None:
    srv = make_server()
    w = JobWatcher(poll_s=0.1)
    first = w.submit(srv.url, {**SHORT, "include_series": True})  # as the viewer's run bodies do
    assert w.view.status == "submitting" and w.view.key == first
    v = wait_for(lambda: _finished(w, first), timeout=120)
    assert v.status == "done" and v.kind == "run" and v.id
    assert v.figure_png is not None and v.figure_png.startswith(PNG)
    # the job's own Delta31 at each leg-1 touchdown, for the viewer's history panel
    with srv.client() as c:
        rows = c.get(f"/v1/jobs/{v.id}/result").json()["result"]["series"]["d31"]
    assert len(v.d31_series) == len(rows) > 0
    assert v.d31_series[0] == (rows[0]["time_s"], rows[0]["d31"])
    assert v.replay is not None and v.replay.d31 == v.d31_series and v.replay.footfall
    html = job_status_html(v)
    assert 'data-job-status="done"' in html and "data:image/png;base64," in html
    assert f"{srv.url}/v1/jobs/{v.id}" in html

    # a job made elsewhere (curl, another viewer) opens by its id, and joins the list
    with srv.client() as c:
        other = submit(c, {**SHORT, "d31_init": [3.0]})
    second = w.open(srv.url, f"  {other['id']} ")
    v2 = wait_for(lambda: _finished(w, second), timeout=120)
    assert v2.status == "done" and v2.figure_png is not None and v2.id == other["id"]
    assert v2.d31_series == () and v2.replay is None  # no series kept: nothing to replay
    assert [x.key for x in w.views] == [second, first]  # newest first


def test_a_queued_or_running_job_is_cancelled_from_its_row(make_server: Any) -> None:
    srv = make_server()
    w = JobWatcher(poll_s=0.1)
    key = w.submit(srv.url, {**SHORT, "duration_s": 60.0})
    wait_for(lambda: (w.get(key) or JobView()).cancellable, timeout=30)
    assert w.cancel(key)
    v = wait_for(lambda: _finished(w, key), timeout=60)
    assert v.status == "cancelled"
    with srv.client() as c:
        assert c.get(f"/v1/jobs/{v.id}").json()["status"] == "cancelled"
    assert not w.cancel(key)  # finished: no second DELETE


def test_a_done_job_replays_in_the_viewers_panels_and_the_walk_comes_back(
    make_server: Any,
) -> None:
    from web.app import ViewerApp
    from web.requests import ReplayJob, StopReplay

    srv = make_server()
    app = ViewerApp("127.0.0.1", 0, api_url=srv.url)
    try:
        app.step(0.3, time.perf_counter() + 600)
        run = app.jobs.submit(srv.url, {**SHORT, "include_series": True})
        ramp = app.jobs.submit(srv.url, RAMP)
        for key in (run, ramp):
            assert wait_for(lambda k=key: _finished(app.jobs, k), timeout=180).status == "done"
        views = {v.key: v for v in app.jobs.views}
        app.painter.readouts(None, None, None)  # the rows: a replay button for each
        rows = app.panels.job_rows._rows
        assert all(rows[k].replay.visible and not rows[k].cancel.visible for k in (run, ramp))

        app.apply(ReplayJob(run))
        app.painter.gait()
        d31, foot = app.panels.d31.content, app.panels.footfall.content
        rid = views[run].id
        assert f'data-replay="{rid}"' in d31 and f'data-replay="{rid}"' in foot
        assert f'data-n-events="{len(views[run].d31_series)}"' in d31
        app.painter.readouts(None, None, None)
        assert app.panels.job_rows.live_again.visible and not rows[run].replay.visible

        app.apply(ReplayJob(ramp))  # a hysteresis job: its Delta31 and its ramp path
        app.painter.gait()
        hid = views[ramp].id
        assert f'data-replay="{hid}"' in app.panels.ramp_plot.content
        assert 'data-plot="ramp-path"' in app.panels.ramp_plot.content
        assert f'data-replay="{hid}"' in app.panels.d31.content
        assert "data-replay" not in app.panels.footfall.content  # the live walk's, again

        app.apply(StopReplay())
        app.painter.gait()
        app.charts.draw()
        assert "data-replay" not in app.panels.d31.content + app.panels.ramp_plot.content
        assert f'data-n-events="{len(app.state.sim.d31_events)}"' in app.panels.d31.content
    finally:
        app.stop()


def test_a_refused_body_an_unknown_id_and_an_absent_api_are_said_in_words(
    make_server: Any,
) -> None:
    srv = make_server()
    w = JobWatcher(poll_s=0.1)
    k = w.submit(srv.url, {**SHORT, "beta": 2.0})
    v = wait_for(lambda: _finished(w, k), timeout=30)
    assert v.status == "refused"
    assert v.message.startswith("the API refused it (HTTP 422): ") and "beta" in v.message
    k = w.open(srv.url, "no-such-job")
    v = wait_for(lambda: _finished(w, k), timeout=30)
    assert v.status == "not found" and "HTTP 404" in v.message
    port = free_port()  # nobody listens there
    k = w.submit(f"http://127.0.0.1:{port}", SHORT)
    v = wait_for(lambda: _finished(w, k), timeout=30)
    assert v.status == "unreachable" and "connection refused" in v.message
    assert f"no API answers at http://127.0.0.1:{port}" in v.message
    for view in (v, *w.views):
        assert "Error" not in view.message  # no Python exception's name
    assert "color:#b00" in job_status_html(v)

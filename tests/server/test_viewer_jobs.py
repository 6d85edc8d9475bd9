"""The viewer's job client (web/jobs.py) against the real service: a job submitted from the
viewer is followed to its end and its figure comes back; an existing job opens by its id; a
refused body and an absent API are said in words, never raised into the viewer's loop."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from api_harness import SHORT, free_port, submit, wait_for

from web.jobs import JobView, JobWatcher, job_status_html

PNG = b"\x89PNG\r\n\x1a\n"


def _finished(w: JobWatcher) -> JobView | None:
    v = w.view
    return v if v.finished and (v.status != "done" or v.figure_png) else None


def test_a_job_submitted_from_the_viewer_is_followed_to_its_figure(
    make_server: Any, tmp_path: Path
) -> None:
    srv = make_server()
    w = JobWatcher(poll_s=0.1)
    w.submit(srv.url, {**SHORT, "include_series": True})  # as the viewer's run bodies do
    assert w.view.status == "submitting"
    v = wait_for(lambda: _finished(w), timeout=120)
    assert v.status == "done" and v.kind == "run" and v.id
    assert v.figure_png is not None and v.figure_png.startswith(PNG)
    # the job's own Delta31 at each leg-1 touchdown, for the viewer's history panel
    with srv.client() as c:
        rows = c.get(f"/v1/jobs/{v.id}/result").json()["result"]["series"]["d31"]
    assert len(v.d31_series) == len(rows) > 0
    assert v.d31_series[0] == (rows[0]["time_s"], rows[0]["d31"])
    html = job_status_html(v)
    assert 'data-job-status="done"' in html and "data:image/png;base64," in html
    assert f"{srv.url}/v1/jobs/{v.id}" in html

    # a job made elsewhere (curl, another viewer) opens by its id
    with srv.client() as c:
        other = submit(c, {**SHORT, "d31_init": [3.0]})
    w.open(srv.url, f"  {other['id']} ")
    v2 = wait_for(lambda: _finished(w) if w.view.id == other["id"] else None, timeout=120)
    assert v2.status == "done" and v2.figure_png is not None
    assert v2.d31_series == ()  # that job kept no series: nothing to draw beside the walk


def test_a_refused_body_and_an_absent_api_are_said_in_words(make_server: Any) -> None:
    srv = make_server()
    w = JobWatcher(poll_s=0.1)
    w.submit(srv.url, {**SHORT, "beta": 2.0})
    v = wait_for(lambda: _finished(w), timeout=30)
    assert v.status == "unreachable" and v.message.startswith("HTTP 422") and "beta" in v.message
    w.open(srv.url, "no-such-job")
    v = wait_for(lambda: _finished(w) if "404" in w.view.message else None, timeout=30)
    assert "HTTP 404" in v.message
    w.submit(f"http://127.0.0.1:{free_port()}", SHORT)  # nobody listens there
    v = wait_for(lambda: _finished(w) if w.view.id == "" else None, timeout=30)
    assert v.status == "unreachable" and "refused" in v.message.lower()
    assert "color:#b00" in job_status_html(v)

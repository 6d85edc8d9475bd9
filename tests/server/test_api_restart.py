"""`kill -9` the real server mid-job, start it again: no job is lost, none is left hanging."""

from __future__ import annotations

import os
import signal
import sqlite3
from collections.abc import Callable

import pytest
from api_harness import SHORT, Server, pid_alive, result_of, submit, wait_for, wait_status

MEDIUM = {"kind": "run", "beta": 0.66, "duration_s": 2.0, "d31_init": [2.0]}


@pytest.mark.parametrize("max_requeues", [1, 0])
def test_kill9_mid_job_then_restart(make_server: Callable[..., Server], max_requeues: int) -> None:
    srv = make_server(workers=1, max_requeues=max_requeues)
    with srv.client() as c:
        finished = wait_status(c, submit(c, SHORT)["id"], {"done", "failed"})
        assert finished["status"] == "done", finished["error"]
        result_before = result_of(c, finished["id"])
        interrupted = submit(c, MEDIUM)
        queued = submit(c, SHORT)
        wait_for(lambda: c.get(f"/v1/jobs/{interrupted['id']}").json()["progress"] > 0)
        workers = srv.workers()
        assert workers

    srv.kill9()
    # the workers die with the server: no orphan keeps simulating or writing
    wait_for(lambda: not any(pid_alive(p) for p in workers), timeout=10)
    with sqlite3.connect(srv.db) as conn:
        left = dict(conn.execute("SELECT id, status FROM jobs").fetchall())
    assert left[interrupted["id"]] == "running" and left[queued["id"]] == "queued"

    again = make_server(db=srv.db, workers=1, max_requeues=max_requeues)
    with again.client() as c:
        job = wait_status(c, interrupted["id"], {"done", "failed"}, timeout=60)
        if max_requeues:
            assert job["status"] == "done", job["error"]
            assert job["requeues"] == 1 and job["attempts"] == 2
            assert "the server stopped while attempt 1 was running" in job["note"]
        else:
            assert job["status"] == "failed"
            assert "the server stopped while this job was running" in job["error"]
            assert "max_requeues = 0" in job["error"]
        assert wait_status(c, queued["id"], {"done", "failed"})["status"] == "done"
        # what was finished before the crash is all still there
        assert c.get(f"/v1/jobs/{finished['id']}").json()["status"] == "done"
        assert result_of(c, finished["id"]) == result_before
        assert c.get("/v1/jobs").json()["total"] == 3


@pytest.mark.parametrize("target", ["server", "group"])
def test_graceful_stop_requeues_running_job(
    make_server: Callable[..., Server], target: str
) -> None:
    """SIGTERM puts the running job back without spending a requeue, whether it reaches the
    server alone (docker stop) or the whole process group (`kill 0` in make run)."""
    srv = make_server(workers=1, max_requeues=0)
    with srv.client() as c:
        job = submit(c, MEDIUM)
        wait_for(lambda: c.get(f"/v1/jobs/{job['id']}").json()["progress"] > 0)
    assert srv.proc is not None
    if target == "group":
        os.killpg(srv.proc.pid, signal.SIGTERM)
    else:
        srv.proc.send_signal(signal.SIGTERM)
    srv.proc.wait(30)
    srv.stop()
    with sqlite3.connect(srv.db) as conn:
        status, note = conn.execute(
            "SELECT status, note FROM jobs WHERE id = ?", (job["id"],)
        ).fetchone()
    assert status == "queued" and "shut down" in note
    again = make_server(db=srv.db, workers=1, max_requeues=0)
    with again.client() as c:
        done = wait_status(c, job["id"], {"done", "failed"}, timeout=60)
        assert done["status"] == "done", done["error"]
        assert done["requeues"] == 0

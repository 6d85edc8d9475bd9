"""Jobs end to end on a real server with real worker processes and real simulations."""

from __future__ import annotations

import csv
import io
import math
import os
import signal
from collections.abc import Callable

import pytest
from api_harness import SHORT, Server, pid_alive, submit, wait_for, wait_status

pytest.importorskip("sim_core")

LONG = {"kind": "run", "beta": 0.66, "duration_s": 120.0, "d31_init": [2.0]}
DIVERGING = {**SHORT, "dt_s": 0.01, "control_dt_s": 0.01, "integrator": "euler"}


def test_submit_poll_result_csv_figure(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=2)
    with srv.client() as c:
        job = submit(c, {**SHORT, "d31_init": [2.0, 1.0], "include_series": True})
        done = wait_status(c, job["id"], {"done", "failed"})
        assert done["status"] == "done", done["error"]
        assert done["progress"] == 1.0 and done["attempts"] == 1
        assert (
            done["started_at"] >= done["created_at"] and done["finished_at"] >= done["started_at"]
        )

        body = c.get(f"/v1/jobs/{job['id']}/result").json()
        assert body["job_id"] == job["id"] and body["kind"] == "run"
        runs = body["result"]["runs"]
        assert len(runs) == 2
        for run in runs:
            assert run["diverged"] is False and run["error"] is None
            assert all(0.0 <= d <= 2 * math.pi for d in run["d31"])
            assert len(run["times_s"]) > 0 and run["times_s"][-1] <= 0.3 + 1e-6
            assert len(run["stance"][0]) == 6

        r = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv"})
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
        rows = list(csv.DictReader(io.StringIO(r.text)))
        assert [float(row["d31_init"]) for row in rows] == [2.0, 1.0]
        assert all(row["beta"] == "0.66" for row in rows)

        r = c.get(f"/v1/jobs/{job['id']}/figure.png")
        assert r.status_code == 200 and r.content.startswith(b"\x89PNG\r\n\x1a\n")

        page = c.get("/v1/jobs", params={"status": "done"}).json()
        assert [j["id"] for j in page["items"]] == [job["id"]]
        assert c.get("/v1/jobs", params={"status": "queued"}).json()["total"] == 0
        # a finished job cannot be cancelled
        r = c.delete(f"/v1/jobs/{job['id']}")
        assert r.status_code == 409 and "already done" in r.json()["detail"]


def test_return_map_pairs_follow_the_runs(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=1)
    with srv.client() as c:
        spec = {"kind": "return_map", "beta": 0.66, "duration_s": 0.5, "d31_init": [1.0, 3.0]}
        job = submit(c, {**spec, "lag": 2})
        done = wait_status(c, job["id"], {"done", "failed"})
        assert done["status"] == "done", done["error"]
        result = c.get(f"/v1/jobs/{job['id']}/result").json()["result"]
        assert result["lag"] == 2
        for d0, run in zip([1.0, 3.0], result["runs"], strict=True):
            d31 = run["d31"]
            mine = [p for p in result["records"] if p["d31_init"] == d0]
            assert [(p["d31_n"], p["d31_n_plus_lag"]) for p in mine] == list(
                zip(d31[:-2], d31[2:], strict=True)
            )
        assert c.get(f"/v1/jobs/{job['id']}/figure.png").status_code == 200


def test_sweep_and_bifurcation_jobs_cover_their_grid(
    make_server: Callable[..., Server],
) -> None:
    srv = make_server(workers=1)
    with srv.client() as c:
        for kind in ("sweep", "bifurcation"):
            spec = {
                "kind": kind,
                "beta_range": {"start": 0.62, "stop": 0.70, "steps": 2},
                "d31_init": [2.0, 3.0],
                "duration_s": 0.5,
            }
            if kind == "bifurcation":
                spec["transient_s"] = 0.2
            job = wait_status(c, submit(c, spec)["id"], {"done", "failed"})
            assert job["status"] == "done", job["error"]
            rows = c.get(f"/v1/jobs/{job['id']}/result").json()["result"]["records"]
            grid = {(round(r["beta"], 3), r["d31_init"]) for r in rows}
            assert grid == {(0.62, 2.0), (0.62, 3.0), (0.7, 2.0), (0.7, 3.0)}
            csv = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv"})
            assert csv.status_code == 200 and csv.text.count("\n") >= 5
            png = c.get(f"/v1/jobs/{job['id']}/figure.png")
            assert png.status_code == 200 and png.content[:4] == b"\x89PNG"


def test_cancel_stops_a_running_job(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=1)
    with srv.client() as c:
        job = submit(c, LONG)
        wait_for(lambda: c.get(f"/v1/jobs/{job['id']}").json()["progress"] > 0, timeout=30)
        (worker,) = srv.workers()

        r = c.delete(f"/v1/jobs/{job['id']}")
        assert r.status_code == 200
        assert r.json()["status"] == "cancelled"

        # the simulation's process is killed, not left to finish in the background
        wait_for(lambda: not pid_alive(worker), timeout=10)
        fresh = srv.wait_workers(1)
        assert worker not in fresh
        job_now = c.get(f"/v1/jobs/{job['id']}").json()
        assert job_now["status"] == "cancelled" and job_now["finished_at"]
        assert "cancelled by request while running" in job_now["note"]
        # cancelling again is harmless; the pool goes on with the next job
        assert c.delete(f"/v1/jobs/{job['id']}").json()["status"] == "cancelled"
        nxt = wait_status(c, submit(c, SHORT)["id"], {"done", "failed"})
        assert nxt["status"] == "done", nxt["error"]
        assert c.get(f"/v1/jobs/{job['id']}").json()["status"] == "cancelled"


def test_cancel_a_queued_job(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0)
    with srv.client() as c:
        job = submit(c, SHORT)
        r = c.delete(f"/v1/jobs/{job['id']}")
        assert r.status_code == 200 and r.json()["status"] == "cancelled"
        assert "while queued" in r.json()["note"]


def test_diverging_simulation_fails_only_its_own_job(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=2)
    with srv.client() as c:
        bad = submit(c, DIVERGING)
        good = submit(c, SHORT)
        bad = wait_status(c, bad["id"], {"done", "failed"})
        good = wait_status(c, good["id"], {"done", "failed"})
        assert bad["status"] == "failed"
        assert "diverged" in bad["error"] and "euler" in bad["error"]
        assert "d31_init = 2" in bad["error"]
        assert good["status"] == "done", good["error"]
        assert c.get("/healthz").json()["workers"]["alive"] == 2


def test_crashed_worker_fails_only_its_own_job(make_server: Callable[..., Server]) -> None:
    """A worker killed from outside (as the OOM killer would) fails its job and is replaced;
    the job queued behind it still runs."""
    srv = make_server(workers=1)
    with srv.client() as c:
        victim = submit(c, LONG)
        other = submit(c, SHORT)
        wait_for(lambda: c.get(f"/v1/jobs/{victim['id']}").json()["progress"] > 0, timeout=30)
        (worker,) = srv.workers()
        os.kill(worker, signal.SIGKILL)
        failed = wait_status(c, victim["id"], {"failed", "done"})
        assert failed["status"] == "failed"
        assert "worker process died (signal 9)" in failed["error"]
        assert wait_status(c, other["id"], {"done", "failed"})["status"] == "done"
        assert worker not in srv.wait_workers(1)

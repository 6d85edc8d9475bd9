"""Jobs end to end on a real server with real worker processes and real simulations."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import signal
import sqlite3
from collections.abc import Callable
from pathlib import Path

import pytest
from api_harness import SHORT, Server, pid_alive, result_of, submit, wait_for, wait_status

from server.kinds.provenance import PROVENANCE_COLUMNS
from sim_core.contract import PHYSICS_VERSION, RETURN_MAP_SKIP, ModelParams, params_hash

LONG = {"kind": "run", "beta": 0.66, "duration_s": 120.0, "d31_init": [2.0]}
# a physical failure at a sound step: on an 80 degree slope the insect flips (measured ~0.25 s)
# 80 deg uphill: flipped at 0.65 s until issue 30; it slides back at -99 cm/s first (0.25 s)
FLIPPING = {**SHORT, "slope_deg": 80.0, "duration_s": 1.0}


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

        body = result_of(c, job["id"])
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
        assert page["items"][0]["eta_s"] is None  # only running jobs have one
        assert c.get("/v1/jobs", params={"status": "queued"}).json()["total"] == 0
        # a finished job cannot be cancelled
        r = c.delete(f"/v1/jobs/{job['id']}")
        assert r.status_code == 409 and "already done" in r.json()["detail"]
        assert "?purge=true" in r.json()["detail"]

        # include_series: the time series as CSV tables and in the figure
        r = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv", "table": "d31"})
        d31_rows = list(csv.DictReader(io.StringIO(r.text)))
        assert [float(x["d31"]) for x in d31_rows if x["run"] == "0"] == runs[0]["d31"]
        assert [float(x["time_s"]) for x in d31_rows if x["run"] == "1"] == runs[1]["d31_times_s"]
        r = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv", "table": "samples"})
        samples = list(csv.DictReader(io.StringIO(r.text)))
        first = [x for x in samples if x["run"] == "0"]
        assert len(first) == len(runs[0]["times_s"])
        legs = ["stance_R1", "stance_L1", "stance_R2", "stance_L2", "stance_R3", "stance_L3"]
        assert [[int(x[k]) for k in legs] for x in first] == runs[0]["stance"]
        assert [float(x["x_m"]) for x in first] == [p[0] for p in runs[0]["body_pos_m"]]

        # a finished job is deleted, with its result, only when asked to purge
        r = c.delete(f"/v1/jobs/{job['id']}", params={"purge": "true"})
        assert r.status_code == 200 and r.json()["status"] == "done"
        # its id answers 410 Gone, saying when and why it went (a tombstone), not a bare 404
        for r in (c.get(f"/v1/jobs/{job['id']}"), c.get(f"/v1/jobs/{job['id']}/result"),
                  c.delete(f"/v1/jobs/{job['id']}", params={"purge": "true"})):  # fmt: skip
            assert r.status_code == 410, r.text
            assert "was deleted at" in r.json()["detail"] and "by request" in r.json()["detail"]
        assert c.get("/v1/jobs/no-such-job").status_code == 404


def test_return_map_pairs_follow_the_runs(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=1)
    with srv.client() as c:
        spec = {"kind": "return_map", "beta": 0.66, "duration_s": 0.5, "d31_init": [1.0, 3.0]}
        job = submit(c, {**spec, "lag": 2})
        done = wait_status(c, job["id"], {"done", "failed"})
        assert done["status"] == "done", done["error"]
        result = result_of(c, job["id"])["result"]
        assert result["lag"] == 2
        for d0, run in zip([1.0, 3.0], result["runs"], strict=True):
            # the core's construction, as `reproduce` builds Fig. 7: the first
            # RETURN_MAP_SKIP touchdowns are the start's transient and make no pair
            d31 = run["d31"][RETURN_MAP_SKIP:]
            mine = [p for p in result["records"] if p["d31_init"] == d0]
            assert [(p["d31_n"], p["d31_n_plus_lag"]) for p in mine] == list(
                zip(d31[:-2], d31[2:], strict=True)
            )
            assert [p["n"] for p in mine] == list(range(RETURN_MAP_SKIP, len(run["d31"]) - 2))
        assert c.get(f"/v1/jobs/{job['id']}/figure.png").status_code == 200


def test_sweep_jobs_cover_their_grid(
    make_server: Callable[..., Server],
) -> None:
    srv = make_server(workers=1)
    with srv.client() as c:
        for kind in ("sweep",):
            spec = {
                "kind": kind,
                "beta_range": {"start": 0.62, "stop": 0.70, "steps": 2},
                "d31_init": [2.0, 3.0],
                "duration_s": 0.5,
            }
            job = wait_status(c, submit(c, spec)["id"], {"done", "failed"})
            assert job["status"] == "done", job["error"]
            rows = result_of(c, job["id"])["result"]["records"]
            grid = {(round(r["beta"], 3), r["d31_init"]) for r in rows}
            assert grid == {(0.62, 2.0), (0.62, 3.0), (0.7, 2.0), (0.7, 3.0)}
            # the core's one settled rule: 0.5 s cannot show a settled drift, so no gait is
            # claimed (issue 30: a 5 s sweep said "tripod" where 40 s slides away)
            assert all(not r["settled"] and r["gait"] == "not settled" for r in rows), rows
            assert all("run longer" in r["settled_why"] or "too few" in r["settled_why"]
                       for r in rows)  # fmt: skip
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
        bad = submit(c, FLIPPING)
        good = submit(c, SHORT)
        bad = wait_status(c, bad["id"], {"done", "failed"})
        good = wait_status(c, good["id"], {"done", "failed"})
        assert bad["status"] == "failed"
        assert "run stopped at t =" in bad["error"] and "implicitfast" in bad["error"]
        assert "d31_init = 2" in bad["error"] and "body slid backwards" in bad["error"]
        # the step is not to blame here, and the message says so
        assert "the insect slid backwards under these conditions" in bad["error"]
        assert "smaller dt_s will not help" in bad["error"]
        assert "try a smaller dt_s" not in bad["error"]
        assert good["status"] == "done", good["error"]
        assert c.get("/healthz").json()["workers"]["alive"] == 2


def test_a_killed_worker_runs_its_job_again_once_then_fails_it_with_both_reasons(
    make_server: Callable[..., Server],
) -> None:
    """A worker killed from outside (kill -9, as the OOM killer would): its job runs again on
    a fresh worker, the first attempt's reason kept in the note; killed again, the job fails
    with both reasons (the job may be what kills it); the job queued behind it still runs."""
    srv = make_server(workers=1)
    with srv.client() as c:
        victim = submit(c, LONG)
        other = submit(c, SHORT)
        wait_for(lambda: c.get(f"/v1/jobs/{victim['id']}").json()["progress"] > 0, timeout=30)
        (worker,) = srv.workers()
        os.kill(worker, signal.SIGKILL)

        def rerunning() -> bool:
            job = c.get(f"/v1/jobs/{victim['id']}").json()
            return job["status"] == "running" and job["attempts"] == 2 and job["progress"] > 0

        wait_for(rerunning, timeout=60)
        again = c.get(f"/v1/jobs/{victim['id']}").json()
        assert "fresh worker (attempt 1: the worker process died (signal 9)" in again["note"]
        assert again["error"] is None
        assert again["requeues"] == 1  # the crash re-queued it (docs/API.md: requeues)
        (second,) = srv.wait_workers(1)
        assert second != worker
        os.kill(second, signal.SIGKILL)
        failed = wait_status(c, victim["id"], {"failed", "done"})
        assert failed["status"] == "failed" and "died 2 times" in failed["error"]
        assert failed["requeues"] == 1  # the second death failed it: not re-queued again
        assert "attempt 1: the worker process died (signal 9)" in failed["error"]
        assert "attempt 2: the worker process died (signal 9)" in failed["error"]
        assert wait_status(c, other["id"], {"done", "failed"})["status"] == "done"
        assert second not in srv.wait_workers(1)


def test_series_tables_need_include_series(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=1)
    with srv.client() as c:
        job = wait_status(c, submit(c, SHORT)["id"], {"done", "failed"})
        r = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv", "table": "d31"})
        assert r.status_code == 409 and "include_series" in r.json()["detail"]


def test_empty_return_map_csv_has_its_header(make_server: Callable[..., Server]) -> None:
    """0.3 s holds ~3 leg-1 touchdowns: with lag 10 there is no pair, but the table's columns
    are still there; and beta comes back as sent."""
    srv = make_server(workers=1)
    with srv.client() as c:
        spec = {"kind": "return_map", "beta": 0.66, "duration_s": 0.3, "d31_init": [2.0]}
        job = wait_status(c, submit(c, {**spec, "lag": 10})["id"], {"done", "failed"})
        assert job["status"] == "done", job["error"]
        assert result_of(c, job["id"])["result"]["records"] == []
        r = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv"})
        assert r.text == ",".join(("d31_init", "n", "d31_n", "d31_n_plus_lag",
                                   *PROVENANCE_COLUMNS)) + "\n"  # fmt: skip


def test_grid_betas_come_back_as_people_write_them(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=1)
    with srv.client() as c:
        spec = {
            "kind": "sweep",
            "beta_range": {"start": 0.6, "stop": 0.7, "steps": 6},
            "duration_s": 0.1,
        }
        job = wait_status(c, submit(c, spec)["id"], {"done", "failed"})
        assert job["status"] == "done", job["error"]
        rows = result_of(c, job["id"])["result"]["records"]
        assert [r["beta"] for r in rows] == [0.6, 0.62, 0.64, 0.66, 0.68, 0.7]
        text = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv"}).text
        assert "0.6599999" not in text and "0.66," in text


def test_hysteresis_job_ramps_down_and_up(make_server: Callable[..., Server]) -> None:
    """The Fig. 6a protocol over REST with tiny durations: beta 0.70 -> 0.62 -> 0.70."""
    srv = make_server(workers=1)
    with srv.client() as c:
        spec = {"kind": "hysteresis", "ramp": {"param": "beta", "start": 0.70, "turn": 0.62,
                "hold_s": 0.2, "ramp_s": 0.4}}  # fmt: skip
        job = submit(c, spec)
        assert job["sim_seconds"] == pytest.approx(1.2)
        job = wait_status(c, job["id"], {"done", "failed"}, timeout=60)
        assert job["status"] == "done", job["error"]
        result = result_of(c, job["id"])["result"]
        assert result["parameter"] == "beta"
        rows = result["records"]
        assert len(rows) >= 6
        values = [r["value"] for r in rows]
        assert max(values) == pytest.approx(0.70) and min(values) < 0.66
        # the first leg goes down, the second up, split at the turn (hold + ramp = 0.6 s)
        assert all(r["leg"] == ("first" if r["time_s"] < 0.6 else "second") for r in rows)
        times = [r["time_s"] for r in rows]
        assert times == sorted(times) and times[-1] <= 1.2
        assert all(0 <= r["d31"] <= 2 * math.pi for r in rows)
        summary = result["summary"]
        assert {"first_leg", "second_leg", "width", "loop"} <= set(summary)
        r = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv"})
        header = ["time_s", "leg", "value", "d31", *PROVENANCE_COLUMNS]
        assert r.text.splitlines()[0] == ",".join(header)
        assert len(r.text.splitlines()) == len(rows) + 1
        png = c.get(f"/v1/jobs/{job['id']}/figure.png")
        assert png.status_code == 200 and png.content[:4] == b"\x89PNG"


def test_running_job_has_an_eta_and_retry_after_follows_it(
    make_server: Callable[..., Server],
) -> None:
    srv = make_server(workers=1, queue_limit=1)
    with srv.client() as c:
        long = submit(c, LONG)
        wait_for(lambda: c.get(f"/v1/jobs/{long['id']}").json()["progress"] >= 0.02, timeout=60)
        running = c.get(f"/v1/jobs/{long['id']}").json()
        assert running["status"] == "running" and running["eta_s"] is not None
        # 98 % of a job left that took >= 0 s for 2 %: the estimate is positive
        assert running["eta_s"] > 0
        queued = submit(c, SHORT)
        assert c.get(f"/v1/jobs/{queued['id']}").json()["eta_s"] is None
        r = c.post("/v1/jobs", json=SHORT)
        assert r.status_code == 429
        retry = int(r.headers["retry-after"])
        eta_now = c.get(f"/v1/jobs/{long['id']}").json()["eta_s"]
        # the slot frees when the running job ends: Retry-After is that job's estimate, not 1 s
        # (both estimates come from its progress, read a moment apart)
        assert retry > 1
        assert retry == pytest.approx(eta_now, rel=0.5, abs=5)
        assert f"retry in about {retry} s" in r.json()["detail"]
        c.delete(f"/v1/jobs/{long['id']}")


def _niceness(pid: int) -> int:
    stat = Path(f"/proc/{pid}/stat").read_text()
    return int(stat[stat.rindex(")") + 2 :].split()[16])  # field 19: nice


def test_workers_run_at_lower_priority(make_server: Callable[..., Server]) -> None:
    # above whatever niceness this test runs at (the server inherits it), so it shows
    target = min(19, os.getpriority(os.PRIO_PROCESS, 0) + 5)
    srv = make_server(workers=2, worker_nice=target)
    workers = srv.wait_workers(2)
    assert srv.proc is not None
    parent = _niceness(srv.proc.pid)
    assert len(workers) == 2
    assert target > parent or parent == 19
    # a worker lowers its priority first thing after it starts
    wait_for(lambda: all(_niceness(pid) == target for pid in workers), timeout=30)
    assert all(os.getpriority(os.PRIO_PROCESS, pid) == target for pid in workers)
    if Path("/proc/self/autogroup").exists():  # autogroup scheduling: niceness per session
        server_group = Path(f"/proc/{srv.proc.pid}/autogroup").read_text().split()[0]

        def own_group(pid: int) -> tuple[str, int]:
            group, _, nice = Path(f"/proc/{pid}/autogroup").read_text().split()
            return group, int(nice)

        wait_for(lambda: all(own_group(pid)[1] == target for pid in workers), timeout=30)
        for pid in workers:
            group, nice = own_group(pid)
            assert group != server_group and nice == target, (group, nice)
    # a worker started after a crash is niced too
    victim = next(iter(workers))
    os.kill(victim, signal.SIGKILL)
    wait_for(lambda: victim not in srv.workers() and len(srv.workers()) == 2, timeout=30)
    srv.wait_workers(2)
    wait_for(lambda: all(_niceness(pid) == target for pid in srv.workers()), timeout=30)


def test_worker_error_shows_no_paths_or_traceback(make_server: Callable[..., Server]) -> None:
    """A job the worker cannot even read (here: a row written past the API's validation, as
    an older server with looser rules could have stored) fails with a message that names the
    field, and carries no file path, traceback or library URL."""
    srv = make_server(workers=1)
    spec = {"kind": "bifurcation", "beta_range": {"start": 0.6, "stop": 0.7}, "transient_s": 1.0}
    with sqlite3.connect(srv.db) as conn:
        conn.execute(
            "INSERT INTO jobs (id, kind, spec, status, sim_seconds, created_at)"
            " VALUES ('legacy', 'bifurcation', ?, 'queued', 88, '2026-01-01T00:00:00.000Z')",
            (json.dumps(spec),),
        )
    with srv.client() as c:
        job = wait_status(c, "legacy", {"done", "failed"})
    assert job["status"] == "failed"
    assert job["error"].startswith("invalid job: transient_s: ")
    assert "allowed fields" in job["error"]
    for leak in ("/", "site-packages", "Traceback", "http", ".py"):
        assert leak not in job["error"], (leak, job["error"])


def test_a_job_walks_on_the_ground_it_names(make_server: Callable[..., Server]) -> None:
    """`ground` reaches the core: the paper's ground walks another walk than the default's."""
    srv = make_server(workers=1)
    with srv.client() as c:
        finals = {}
        for ground in ("constraint", "penalty"):
            job = submit(c, {**SHORT, "duration_s": 0.5, "include_series": True, "ground": ground})
            job = wait_status(c, job["id"], {"done", "failed"}, timeout=60)
            assert job["status"] == "done", job["error"]
            (run,) = result_of(c, job["id"])["result"]["runs"]
            finals[ground] = run["d31"]
        assert finals["constraint"] and finals["penalty"]
        assert finals["constraint"] != finals["penalty"]


def test_every_csv_names_its_physics_and_conditions(make_server: Callable[..., Server]) -> None:
    """Every table a job exports ends with its provenance (one function for every kind): the
    physics' version and the parameters' hash as the result cache names them, the ground, the
    numerics, the mass and the slope; a condition the job varies is the row's, left blank."""
    srv = make_server(workers=1)
    run = {**SHORT, "body_mass_g": 4.0, "slope_deg": 5.0, "ground": "penalty",
           "dt_s": 2.5e-5, "include_series": True}  # fmt: skip
    # the flat shape of before the job held a `Ramp` (deprecated, still accepted and run)
    ramp = {"kind": "hysteresis", "parameter": "slope_deg", "start": 0.0, "turn": 4.0,
            "hold_s": 0.1, "ramp_s": 0.1, "body_mass_g": 2.5}  # fmt: skip
    with srv.client() as c:
        ran = wait_status(c, submit(c, run)["id"], {"done", "failed"}, timeout=60)
        ramped = wait_status(c, submit(c, ramp)["id"], {"done", "failed"}, timeout=60)
        assert ran["status"] == ramped["status"] == "done", (ran["error"], ramped["error"])
        tables = {
            t: list(csv.DictReader(io.StringIO(c.get(
                f"/v1/jobs/{ran['id']}/result", params={"format": "csv", "table": t}).text)))
            for t in ("records", "d31", "samples")
        }  # fmt: skip
        ramp_rows = list(csv.DictReader(io.StringIO(
            c.get(f"/v1/jobs/{ramped['id']}/result", params={"format": "csv"}).text)))  # fmt: skip
        stamp = result_of(c, ran["id"])["result"]["provenance"]
    want = {"physics_version": PHYSICS_VERSION,
            "params_hash": params_hash(ModelParams.of(ground="penalty")), "ground": "penalty",
            "integrator": "implicitfast", "dt_s": "2.5e-05", "control_dt_s": "0.0005",
            "body_mass_g": "4.0", "slope_deg": "5.0", "setting": "", "params": "{}"}  # fmt: skip
    assert params_hash(ModelParams.of(ground="penalty")) != params_hash(ModelParams())
    for name, rows in tables.items():
        assert rows, name
        for row in rows:
            assert {k: row[k] for k in PROVENANCE_COLUMNS} == want, (name, row)
    assert stamp == {**want, "dt_s": 2.5e-5, "control_dt_s": 5e-4, "body_mass_g": 4.0,
                     "slope_deg": 5.0, "setting": None, "params": {}}  # fmt: skip
    assert ramp_rows and all(r["slope_deg"] == "" and r["body_mass_g"] == "2.5" for r in ramp_rows)
    assert {r["ground"] for r in ramp_rows} == {"constraint"}

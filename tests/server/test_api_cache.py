"""One cache for every door, on the real service (uvicorn, worker processes, SQLite): a job
submitted twice is served from the result cache the second time, its record says so and its
result is the same bytes; a job whose worker is killed mid-way resumes from the simulations it
had finished, and its result is an uninterrupted run's."""

from __future__ import annotations

import json
import os
import signal
import time
from collections.abc import Callable
from datetime import datetime
from pathlib import Path
from typing import Any

import httpx
from api_harness import Server, result_of, submit, wait_for, wait_status

# 2 betas x 3 held Delta31: 6 probes of the drift surface, no refinement
SURFACE = {"kind": "surface", "beta_range": {"start": 0.64, "stop": 0.655, "steps": 2},
           "d31_lo": 1.9, "d31_hi": 2.3, "d31_step": 0.2, "refine": False}  # fmt: skip
# 16 runs of 1 s: two chunks of 8 on one worker, each a few seconds
SWEEP = {"kind": "sweep", "beta_range": {"start": 0.62, "stop": 0.70, "steps": 4},
         "d31_init": [1.0, 2.0, 3.0, 4.0], "duration_s": 1.0}  # fmt: skip


def _seconds(job: dict[str, Any]) -> float:
    start, end = (datetime.fromisoformat(job[k].replace("Z", "+00:00"))
                  for k in ("started_at", "finished_at"))  # fmt: skip
    return (end - start).total_seconds()


def _result_bytes(c: httpx.Client, job_id: str) -> tuple[str, bytes]:
    """The result as JSON text (its `result`: the job id is the envelope's) and its CSV."""
    body = result_of(c, job_id)
    csv = c.get(f"/v1/jobs/{job_id}/result", params={"format": "csv"}).content
    return json.dumps(body["result"]), csv


def test_a_job_submitted_twice_is_served_from_the_cache(
    make_server: Callable[..., Server], tmp_path: Path
) -> None:
    srv = make_server(workers=1)
    with srv.client() as c:
        t0 = time.perf_counter()
        first = wait_status(c, submit(c, SURFACE)["id"], {"done", "failed"}, timeout=300)
        wall_first = time.perf_counter() - t0
        assert first["status"] == "done", first["error"]
        t0 = time.perf_counter()
        second = wait_status(c, submit(c, SURFACE)["id"], {"done", "failed"}, timeout=60)
        wall_second = time.perf_counter() - t0
        assert second["status"] == "done", second["error"]
        assert second["id"] != first["id"]  # no key: a second job, but no second computation
        made, read = first["simulations"], second["simulations"]
        assert made == {"tasks": 6, "computed": 6, "from_cache": 0, "backend": "inline"}
        assert read == {"tasks": 6, "computed": 0, "from_cache": 6, "backend": "inline"}
        assert _result_bytes(c, second["id"]) == _result_bytes(c, first["id"])
        # the cache is the server's configured folder, one file per probe
        assert len(list((tmp_path / "cache").glob("*.json"))) == 6
        print(
            f"\nsurface job of 6 probes: first {wall_first:.2f} s (worker {_seconds(first):.2f}"
            f" s), resubmitted {wall_second:.2f} s (worker {_seconds(second):.3f} s)"
        )
        assert _seconds(second) < _seconds(first) / 3


def test_a_job_whose_worker_is_killed_resumes_from_its_finished_simulations(
    make_server: Callable[..., Server], tmp_path: Path
) -> None:
    cache = tmp_path / "cache"
    srv = make_server(workers=1)
    with srv.client() as c:
        job = submit(c, SWEEP)
        # the first chunk of 8 is stored the moment it returns; kill the worker in the second
        wait_for(lambda: len(list(cache.glob("*.json"))) >= 8, timeout=240, every=0.02)
        (worker,) = srv.workers()
        os.kill(worker, signal.SIGKILL)
        finished = len(list(cache.glob("*.json")))
        assert c.get(f"/v1/jobs/{job['id']}").json()["status"] in ("running", "queued")
        done = wait_status(c, job["id"], {"done", "failed"}, timeout=240)
        assert done["status"] == "done", done["error"]
        assert done["attempts"] == 2 and "fresh worker" in done["note"]
        sims = done["simulations"]
        assert 8 <= finished < 16 and sims["from_cache"] == finished
        assert sims["tasks"] == 16 and sims["computed"] == 16 - finished
        resumed = _result_bytes(c, job["id"])
    srv.stop()
    # the same job, uninterrupted, on a server with a cache of its own: the same bytes
    fresh = make_server(workers=1, cache_dir=tmp_path / "fresh")
    with fresh.client() as c:
        whole = wait_status(c, submit(c, SWEEP)["id"], {"done", "failed"}, timeout=240)
        assert whole["status"] == "done", whole["error"]
        assert whole["simulations"]["computed"] == 16 and whole["attempts"] == 1
        assert _result_bytes(c, whole["id"]) == resumed
    print(
        f"\nkilled after {finished} of 16 runs were stored: the re-run read "
        f"{sims['from_cache']} from the cache and computed {sims['computed']}"
    )

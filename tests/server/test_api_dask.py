"""Jobs on the cluster engine: the real service pointed at a real `distributed.LocalCluster`
(started here) sends its jobs' chunks there, with the same result bytes as its own workers
compute, progress as chunks come back, and a cancel that leaves nothing on the cluster.

The cluster runs its worker as threads of this test process (processes=False) and speaks TCP:
the service's worker processes reach it over the network as they would a remote scheduler
(what the path depends on), while a worker thread starts in a fraction of a second and needs no
second copy of MuJoCo in memory on a small test machine; how the cluster hosts its workers
changes no number (`sim_core.runs`). Holding the scheduler in this process also lets the test
read its task table directly."""

from __future__ import annotations

import importlib.util
import json
import logging
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from api_harness import Server, result_of, submit, wait_for, wait_status

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("distributed") is None,
    reason="dask.distributed not installed (extra 'cluster')",
)

# 12 runs: two chunks of 6 on a one-thread cluster, so progress is seen between them
SWEEP = {"kind": "sweep", "beta_range": {"start": 0.62, "stop": 0.70, "steps": 3},
         "d31_init": [1.0, 2.0, 3.0, 4.0], "duration_s": 1.0}  # fmt: skip
LONG = {"kind": "run", "beta": 0.66, "duration_s": 8.0, "d31_init": [2.0]}


@pytest.fixture
def cluster() -> Iterator[Any]:
    from distributed import LocalCluster

    # a closed client's comm is logged as an error on shutdown: noise, not a failure
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp",
                      dashboard_address=None) as c:  # fmt: skip
        yield c


def _result(srv: Server, job_id: str) -> tuple[str, bytes]:
    with srv.client() as c:
        body = result_of(c, job_id)
        return json.dumps(body["result"]), c.get(
            f"/v1/jobs/{job_id}/result", params={"format": "csv"}
        ).content


def test_a_job_on_a_dask_cluster_gives_the_local_bytes(
    make_server: Callable[..., Server], cluster: Any, tmp_path: Path
) -> None:
    srv = make_server(workers=1, dask_address=cluster.scheduler_address)
    seen: list[float] = []
    with srv.client() as c:
        job = submit(c, SWEEP)

        def finished() -> dict[str, Any] | None:
            now = c.get(f"/v1/jobs/{job['id']}").json()
            seen.append(now["progress"])
            return now if now["status"] in ("done", "failed") else None

        done = wait_for(finished, timeout=300, every=0.05)
    assert done["status"] == "done", done["error"]
    assert done["simulations"] == {"tasks": 12, "computed": 12, "from_cache": 0,
                                   "backend": "dask"}  # fmt: skip
    assert any(0 < x < 1 for x in seen), seen  # moved when the first chunk came back
    # the chunks ran on the cluster (its scheduler named them), the results came back to
    # the service's cache
    assert "execute_chunk" in cluster.scheduler.task_prefixes
    assert len(list((tmp_path / "cache").glob("*.json"))) == 12
    on_dask = _result(srv, done["id"])
    srv.stop()
    local = make_server(workers=1, cache_dir=tmp_path / "local")
    with local.client() as c:
        here = wait_status(c, submit(c, SWEEP)["id"], {"done", "failed"}, timeout=300)
    assert here["status"] == "done" and here["simulations"]["backend"] == "inline"
    assert _result(local, here["id"]) == on_dask


def test_cancelling_a_dask_job_leaves_nothing_on_the_cluster(
    make_server: Callable[..., Server], cluster: Any
) -> None:
    """Cancel SIGKILLs the job's worker process; its client's connection dies with it, and
    the scheduler forgets that client's futures: nothing of the job stays queued there."""
    scheduler = cluster.scheduler
    srv = make_server(workers=1, dask_address=cluster.scheduler_address)
    with srv.client() as c:
        job = submit(c, LONG)
        wait_for(lambda: any(ts.state == "processing" for ts in list(scheduler.tasks.values())),
                 timeout=120, every=0.02)  # fmt: skip
        clients = set(scheduler.clients) - {"fire-and-forget"}
        assert len(clients) == 1  # the job's worker's client
        (worker,) = srv.workers()
        r = c.delete(f"/v1/jobs/{job['id']}")
        assert r.status_code == 200 and r.json()["status"] == "cancelled"
        wait_for(lambda: not scheduler.tasks, timeout=30)
        assert not set(scheduler.clients) & clients
        assert worker not in srv.wait_workers(1)
        assert c.get(f"/v1/jobs/{job['id']}").json()["status"] == "cancelled"
    # the chunk that was running finishes on its worker thread and is dropped: let it end
    # before the cluster closes
    wait_for(
        lambda: not any(w.state.executing_count for w in cluster.workers.values()),
        timeout=120,
        every=0.2,
    )

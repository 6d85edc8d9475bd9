"""Retention: finished jobs beyond the configured count go at start-up and periodically; jobs
that are queued or running are never touched."""

from __future__ import annotations

import sqlite3
from collections.abc import Callable

from api_harness import SHORT, Server, submit, wait_for


def _statuses(srv: Server) -> dict[str, str]:
    with sqlite3.connect(srv.db) as conn:
        return {str(i): str(s) for i, s in conn.execute("SELECT id, status FROM jobs")}


def test_retention_count_at_startup_and_periodically(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0)
    with srv.client() as c:
        ids = [submit(c, SHORT)["id"] for _ in range(4)]
        for job_id in ids[:3]:
            assert c.delete(f"/v1/jobs/{job_id}").status_code == 200  # cancelled = finished
    srv.stop()
    assert len(_statuses(srv)) == 4

    # start-up: keep the newest 2 finished jobs; the queued one stays
    again = make_server(db=srv.db, workers=0, retention_count=2, retention_interval_s=0.2)
    assert _statuses(again) == {ids[1]: "cancelled", ids[2]: "cancelled", ids[3]: "queued"}
    with again.client() as c:
        # periodically: a newly finished job pushes the oldest kept one out
        c.delete(f"/v1/jobs/{ids[3]}")
        wait_for(lambda: ids[1] not in _statuses(again), timeout=30)
        assert _statuses(again) == {ids[2]: "cancelled", ids[3]: "cancelled"}
        assert c.get("/v1/jobs").json()["total"] == 2

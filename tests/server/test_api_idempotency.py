"""Idempotent submission and tombstones on the real service: a POST repeated with one
`Idempotency-Key` (a client's retry after a network error) gives one job, however often and
however fast it is repeated; a key is remembered for `idempotency_ttl_s`; a deleted job's id
(and a key that made it) answers 410 Gone saying when and why, for `tombstone_days`."""

from __future__ import annotations

import sqlite3
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import httpx
from api_harness import SHORT, Server, wait_for


def _count(srv: Server) -> int:
    with sqlite3.connect(srv.db) as conn:
        return int(conn.execute("SELECT count(*) FROM jobs").fetchone()[0])


def test_one_key_gives_one_job(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0)
    key = {"Idempotency-Key": "2f1c7a52-7a0e-4a59-9d7e-1a3a9d0f5b11"}
    with srv.client() as c:
        first = c.post("/v1/jobs", json=SHORT, headers=key)
        assert first.status_code == 202 and "idempotent-replayed" not in first.headers
        again = c.post("/v1/jobs", json=SHORT, headers=key)
        assert again.status_code == 202 and again.headers["idempotent-replayed"] == "true"
        assert again.json()["id"] == first.json()["id"]
        assert again.headers["location"] == first.headers["location"]
        # the same job however it is spelled: key order, a default written out
        respelled = {"d31_init": [2.0], "kind": "run", "duration_s": 0.3, "beta": 0.66,
                     "slope_deg": 0.0}  # fmt: skip
        assert c.post("/v1/jobs", json=respelled, headers=key).json()["id"] == first.json()["id"]
        # another job under the same key is the client's mistake: refused, with the job named
        other = c.post("/v1/jobs", json={**SHORT, "beta": 0.7}, headers=key)
        assert other.status_code == 422
        (issue,) = other.json()["detail"]
        assert issue["loc"] == ["header", "Idempotency-Key"]
        assert first.json()["id"] in issue["msg"] and "another job spec" in issue["msg"]
        # without a key, or with another, a POST is a new job
        assert c.post("/v1/jobs", json=SHORT).json()["id"] != first.json()["id"]
        new = c.post("/v1/jobs", json=SHORT, headers={"Idempotency-Key": "another"})
        assert new.json()["id"] != first.json()["id"]
        bad = c.post("/v1/jobs", json=SHORT, headers={"Idempotency-Key": "x" * 300})
        assert bad.status_code == 422 and "1 to 255" in bad.json()["detail"][0]["msg"]
    assert _count(srv) == 3


def test_retries_racing_each_other_still_make_one_job(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0)

    def post(_: int) -> str:
        with httpx.Client(base_url=srv.url, timeout=30.0) as c:
            r = c.post("/v1/jobs", json=SHORT, headers={"Idempotency-Key": "race"})
            assert r.status_code == 202, r.text
            return str(r.json()["id"])

    with ThreadPoolExecutor(8) as pool:
        ids = set(pool.map(post, range(16)))
    assert len(ids) == 1 and _count(srv) == 1


def test_a_key_is_forgotten_after_its_time(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0, idempotency_ttl_s=1.0, retention_interval_s=0.5)
    key = {"Idempotency-Key": "short-lived"}
    with srv.client() as c:
        first = c.post("/v1/jobs", json=SHORT, headers=key).json()["id"]
        time.sleep(1.5)
        later = c.post("/v1/jobs", json=SHORT, headers=key)
        assert later.status_code == 202 and "idempotent-replayed" not in later.headers
        assert later.json()["id"] != first
    # the housekeeping thread drops expired keys from the table
    with sqlite3.connect(srv.db) as conn:
        wait_for(lambda: conn.execute("SELECT count(*) FROM idempotency_keys").fetchone()[0] == 0,
                 timeout=10)  # fmt: skip


def test_a_deleted_job_answers_410_with_when_and_why(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0, retention_count=0, retention_interval_s=0.2)
    key = {"Idempotency-Key": "deleted-later"}
    with srv.client() as c:
        job = c.post("/v1/jobs", json=SHORT, headers=key).json()
        assert c.delete(f"/v1/jobs/{job['id']}").json()["status"] == "cancelled"
        # retention keeps no finished job: it goes at the next pass
        wait_for(lambda: c.get(f"/v1/jobs/{job['id']}").status_code == 410, timeout=10)
        detail = c.get(f"/v1/jobs/{job['id']}").json()["detail"]
        assert f"job {job['id']} (run, created {job['created_at']})" in detail
        assert "by retention (only the newest retention_count = 0" in detail
        assert c.get(f"/v1/jobs/{job['id']}/result").status_code == 410
        assert c.get(f"/v1/jobs/{job['id']}/figure.png").status_code == 410
        assert c.delete(f"/v1/jobs/{job['id']}").status_code == 410
        # the key that made it says so too, rather than queueing the job again
        replay = c.post("/v1/jobs", json=SHORT, headers=key)
        assert replay.status_code == 410 and "since deleted" in replay.json()["detail"]
        assert c.get("/v1/jobs/never-was").status_code == 404


def test_a_tombstone_is_forgotten_after_tombstone_days(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0, tombstone_days=2e-5)  # 1.7 s
    with srv.client() as c:
        job = c.post("/v1/jobs", json=SHORT).json()
        c.delete(f"/v1/jobs/{job['id']}")
        r = c.delete(f"/v1/jobs/{job['id']}", params={"purge": "true"})
        assert r.status_code == 200
        assert c.get(f"/v1/jobs/{job['id']}").status_code == 410
        time.sleep(2.0)
        assert c.get(f"/v1/jobs/{job['id']}").status_code == 404

"""Refusals: a full queue gets 429 with Retry-After; without the token, 401 and no change."""

from __future__ import annotations

import sqlite3
from collections.abc import Callable

from api_harness import SHORT, Server, submit


def _rows(srv: Server) -> list[tuple[str, str]]:
    with sqlite3.connect(srv.db) as conn:
        return [(str(a), str(b)) for a, b in conn.execute("SELECT id, status FROM jobs")]


def test_queue_limit_gets_429_with_retry_after(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0, queue_limit=3)
    with srv.client() as c:
        ids = [submit(c, SHORT)["id"] for _ in range(3)]
        r = c.post("/v1/jobs", json=SHORT)
        assert r.status_code == 429
        assert int(r.headers["retry-after"]) >= 1
        assert "queue_limit = 3" in r.json()["detail"]
        assert len(_rows(srv)) == 3
        # a freed slot (here: a cancel) lets the next one in
        assert c.delete(f"/v1/jobs/{ids[0]}").status_code == 200
        assert c.post("/v1/jobs", json=SHORT).status_code == 202
        assert c.post("/v1/jobs", json=SHORT).status_code == 429
        assert c.get("/healthz").json()["queued"] == 3


def test_token_guards_mutations(make_server: Callable[..., Server]) -> None:
    srv = make_server(workers=0, api_token="s3cret-token")
    good = {"Authorization": "Bearer s3cret-token"}
    with srv.client() as c:
        # issue 30: a missing, a malformed and a wrong token are told apart
        for headers, says in (
            ({}, "(none was sent)"),
            ({"Authorization": "Bearer wrong"}, "is not this server's token"),
            ({"Authorization": "s3cret-token"}, "is not of the form 'Bearer <token>'"),
        ):
            r = c.post("/v1/jobs", json=SHORT, headers=headers)
            assert r.status_code == 401, r.text
            assert r.headers["www-authenticate"] == "Bearer"
            assert says in r.json()["detail"], r.text
        assert _rows(srv) == []
        job = submit(c, SHORT, headers=good)
        before = _rows(srv)
        r = c.delete(f"/v1/jobs/{job['id']}")
        assert r.status_code == 401
        assert _rows(srv) == before == [(job["id"], "queued")]
        # reading needs no token
        assert c.get(f"/v1/jobs/{job['id']}").status_code == 200
        assert c.get("/v1/jobs").json()["total"] == 1
        assert c.get("/healthz").status_code == 200
        r = c.delete(f"/v1/jobs/{job['id']}", headers=good)
        assert r.status_code == 200 and r.json()["status"] == "cancelled"

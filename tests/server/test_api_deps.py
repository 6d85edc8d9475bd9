"""Dependencies are declared once (server/deps.py) and can be swapped per app through
`app.dependency_overrides`; the app runs under a real uvicorn with a real SQLite file."""

from __future__ import annotations

import sqlite3
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx
import uvicorn
from api_harness import SHORT, free_port, wait_for
from fastapi import FastAPI

from server.app import create_app
from server.deps import get_store, require_token
from server.jobs import JobStore
from server.settings import Settings


@contextmanager
def serve(app: FastAPI) -> Iterator[str]:
    """Run `app` under uvicorn in a thread (lifespan included) and yield its base URL."""
    port = free_port()
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    try:
        wait_for(lambda: server.started, timeout=30)
        yield f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(30)


def _ids(db: Path) -> list[str]:
    with sqlite3.connect(db) as conn:
        return [str(r[0]) for r in conn.execute("SELECT id FROM jobs")]


def test_token_check_can_be_overridden(tmp_path: Path) -> None:
    app = create_app(Settings(db_path=tmp_path / "a.sqlite3", workers=0, api_token="t0ken"))
    with serve(app) as url:
        assert httpx.post(f"{url}/v1/jobs", json=SHORT).status_code == 401
        # e.g. a lab that authenticates in its proxy: the override lets every request through
        app.dependency_overrides[require_token] = lambda: None
        r = httpx.post(f"{url}/v1/jobs", json=SHORT)
        assert r.status_code == 202, r.text
        app.dependency_overrides.clear()
        assert httpx.post(f"{url}/v1/jobs", json=SHORT).status_code == 401
    assert _ids(tmp_path / "a.sqlite3") == [r.json()["id"]]


def test_store_can_be_overridden(tmp_path: Path) -> None:
    other = JobStore(tmp_path / "other.sqlite3")
    other.init()
    app = create_app(Settings(db_path=tmp_path / "main.sqlite3", workers=0))
    app.dependency_overrides[get_store] = lambda: other
    with serve(app) as url:
        job = httpx.post(f"{url}/v1/jobs", json=SHORT).json()
        assert httpx.get(f"{url}/v1/jobs/{job['id']}").json()["status"] == "queued"
    # the job went to the overriding store's file, not the app's own
    assert _ids(tmp_path / "other.sqlite3") == [job["id"]]
    assert _ids(tmp_path / "main.sqlite3") == []

"""Test harness: real servers, `python -m server` (uvicorn in-process) on a free loopback port
with its own SQLite file. Each server runs in its own session, so teardown can kill the whole
group (server and workers) whatever a test did to it.
"""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import pytest

REPO = Path(__file__).resolve().parents[2]

# Short simulations keep the suite quick; these still cover several leg-1 touchdowns.
SHORT = {"kind": "run", "beta": 0.66, "duration_s": 0.3, "d31_init": [2.0]}


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def wait_for(pred: Callable[[], Any], timeout: float = 30.0, every: float = 0.05) -> Any:
    """Poll until `pred()` is truthy; bounded, and the failure says what never happened."""
    deadline = time.monotonic() + timeout
    while True:
        value = pred()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"condition not met within {timeout} s: {pred}")
        time.sleep(every)


def children_of(pid: int) -> set[int]:
    """Direct children of `pid`, read from /proc (the worker processes of a server)."""
    out: set[int] = set()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2 :].split()
        if int(fields[1]) == pid and fields[0] != "Z":
            out.add(int(entry.name))
    return out


def pid_alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rindex(")") + 2 :].split()[0] != "Z"


@dataclass
class Server:
    db: Path
    port: int
    env: dict[str, str]
    log: Path
    proc: subprocess.Popen[bytes] | None = None
    pgids: list[int] = field(default_factory=list)

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def start(self, timeout: float = 30.0) -> Server:
        env = {**os.environ, **self.env, "PYTHONPATH": str(REPO)}
        with self.log.open("ab") as log:
            self.proc = subprocess.Popen(
                [sys.executable, "-m", "server", "--port", str(self.port), "--db", str(self.db)],
                cwd=self.db.parent,  # MuJoCo writes MUJOCO_LOG.TXT to the cwd
                env=env,
                stdout=log,
                stderr=subprocess.STDOUT,
                start_new_session=True,
            )
        self.pgids.append(self.proc.pid)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise AssertionError(f"server exited early:\n{self.log.read_text()[-3000:]}")
            try:
                if httpx.get(f"{self.url}/healthz", timeout=1.0).status_code == 200:
                    return self
            except httpx.HTTPError:
                pass
            time.sleep(0.05)
        raise AssertionError(f"server did not come up:\n{self.log.read_text()[-3000:]}")

    def client(self, **kw: Any) -> httpx.Client:
        return httpx.Client(base_url=self.url, timeout=10.0, **kw)

    def workers(self) -> set[int]:
        """Worker processes: children started by multiprocessing's spawn (not its resource
        tracker, which is a child too)."""
        assert self.proc is not None
        out = set()
        for pid in children_of(self.proc.pid):
            try:
                cmdline = Path(f"/proc/{pid}/cmdline").read_bytes()
            except OSError:
                continue
            if b"spawn_main" in cmdline:
                out.add(pid)
        return out

    def wait_workers(self, n: int, timeout: float = 30.0) -> set[int]:
        """Wait until n workers are alive and have reported ready (healthz counts them)."""

        def ready() -> bool:
            h = httpx.get(f"{self.url}/healthz", timeout=2.0).json()
            return bool(h["workers"]["alive"] == n and len(self.workers()) >= n)

        wait_for(ready, timeout)
        return self.workers()

    def kill9(self) -> None:
        """SIGKILL the server process only (not its group): what a crash or OOM kill does."""
        assert self.proc is not None
        self.proc.send_signal(signal.SIGKILL)
        self.proc.wait(10)

    def stop(self) -> None:
        """Graceful stop (SIGTERM), then make sure nothing of it is left."""
        if self.proc is not None and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(20)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(5)
        self.kill_groups()

    def kill_groups(self) -> None:
        for pgid in self.pgids:
            try:
                os.killpg(pgid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass


@pytest.fixture
def make_server(tmp_path: Path) -> Iterator[Callable[..., Server]]:
    """Factory: make_server(workers=1, queue_limit=..., db=...) -> a started Server; settings
    as keywords (their INSECT_GAIT_* variables), the result cache under the test's tmp_path."""
    started: list[Server] = []

    def make(db: Path | None = None, start: bool = True, **settings: Any) -> Server:
        env = {f"INSECT_GAIT_{k.upper()}": str(v) for k, v in settings.items()}
        env.setdefault("INSECT_GAIT_WORKERS", "1")
        env.setdefault("INSECT_GAIT_LOG_LEVEL", "warning")
        # the test's own result cache (every server of one test shares it), never the
        # checkout's: a test that times a job or kills it mid-way must see it compute
        env.setdefault("INSECT_GAIT_CACHE_DIR", str(tmp_path / "cache"))
        server = Server(
            db=db or tmp_path / "jobs.sqlite3",
            port=free_port(),
            env=env,
            log=tmp_path / f"server-{len(started)}.log",
        )
        started.append(server)
        return server.start() if start else server

    yield make
    for server in started:
        server.stop()


def submit(client: httpx.Client, spec: dict[str, Any], **kw: Any) -> dict[str, Any]:
    r = client.post("/v1/jobs", json=spec, **kw)
    assert r.status_code == 202, r.text
    body: dict[str, Any] = r.json()
    return body


def wait_status(
    client: httpx.Client, job_id: str, statuses: set[str], timeout: float = 30.0
) -> dict[str, Any]:
    def check() -> dict[str, Any] | None:
        job: dict[str, Any] = client.get(f"/v1/jobs/{job_id}").json()
        return job if job["status"] in statuses else None

    result: dict[str, Any] = wait_for(check, timeout)
    return result


def result_of(client: httpx.Client, job_id: str) -> dict[str, Any]:
    """GET a done job's result as JSON, checked against the schema the API publishes for it
    (`server.schemas.JobResult`: its kind's result model, as in /openapi.json)."""
    from pydantic import TypeAdapter

    from server.schemas import JobResult

    r = client.get(f"/v1/jobs/{job_id}/result")
    assert r.status_code == 200, r.text
    body: dict[str, Any] = r.json()
    checked = TypeAdapter(JobResult).validate_python(body)
    assert checked.result.kind == body["kind"] == body["result"]["kind"]
    return body

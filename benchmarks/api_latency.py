"""Latency of `GET /v1/jobs/{id}` while every worker is busy simulating (issue 6: p99 < 50 ms).

Starts a real server (`python -m server`) on a free loopback port with a throw-away database,
fills every worker with a long simulation, then times a bounded number of status polls from a
few client threads. Prints p50/p90/p99/max and stops everything it started.

    .venv/bin/python benchmarks/api_latency.py [--requests 2000] [--clients 4] [--workers N]
"""

from __future__ import annotations

import argparse
import http.client
import json
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
LONG_JOB = {"kind": "run", "beta": 0.66, "duration_s": 600.0, "d31_init": [2.0]}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _request(conn: http.client.HTTPConnection, method: str, path: str, body: Any = None) -> Any:
    payload = json.dumps(body).encode() if body is not None else None
    headers = {"Content-Type": "application/json"} if payload else {}
    conn.request(method, path, body=payload, headers=headers)
    resp = conn.getresponse()
    data = resp.read()
    if resp.status >= 400:
        raise RuntimeError(f"{method} {path} -> {resp.status}: {data[:200]!r}")
    return json.loads(data)


def _wait(pred: Any, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not pred():
        if time.monotonic() > deadline:
            raise RuntimeError(f"timed out waiting for {what}")
        time.sleep(0.1)


def _percentile(xs: list[float], q: float) -> float:
    ordered = sorted(xs)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--requests", type=int, default=2000, help="status polls in all (max 20000)")
    ap.add_argument("--clients", type=int, default=4, help="concurrent client threads")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="server workers")
    args = ap.parse_args()
    n_requests = max(1, min(args.requests, 20_000))
    clients = max(1, min(args.clients, 32))

    port = _free_port()
    tmp = tempfile.TemporaryDirectory(prefix="insect-gait-bench-")
    env = {
        **os.environ,
        "PYTHONPATH": str(REPO),
        "INSECT_GAIT_WORKERS": str(args.workers),
        "INSECT_GAIT_LOG_LEVEL": "warning",
    }
    log = open(Path(tmp.name) / "server.log", "wb")
    server = subprocess.Popen(
        [sys.executable, "-m", "server", "--port", str(port), "--db", f"{tmp.name}/b.sqlite3"],
        cwd=tmp.name,
        env=env,
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )
    try:
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10)

        def healthy() -> Any:
            try:
                return _request(conn, "GET", "/healthz")
            except (OSError, http.client.HTTPException, RuntimeError):
                conn.close()
                return None

        _wait(lambda: (h := healthy()) and h["workers"]["alive"] == args.workers, 60, "server")
        ids = [_request(conn, "POST", "/v1/jobs", LONG_JOB)["id"] for _ in range(args.workers)]
        _wait(lambda: healthy()["workers"]["busy"] == args.workers, 60, "all workers busy")
        _wait(
            lambda: all(_request(conn, "GET", f"/v1/jobs/{i}")["progress"] > 0 for i in ids),
            120,
            "simulations to report progress",
        )

        latencies: list[float] = []
        lock = threading.Lock()
        per_client = [n_requests // clients + (i < n_requests % clients) for i in range(clients)]

        def poll(count: int, offset: int) -> None:
            c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
            mine: list[float] = []
            for k in range(count):
                t0 = time.perf_counter()
                _request(c, "GET", f"/v1/jobs/{ids[(offset + k) % len(ids)]}")
                mine.append(time.perf_counter() - t0)
            c.close()
            with lock:
                latencies.extend(mine)

        threads = [
            threading.Thread(target=poll, args=(count, i)) for i, count in enumerate(per_client)
        ]
        t0 = time.perf_counter()
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        wall = time.perf_counter() - t0
        busy = healthy()["workers"]["busy"]

        ms = [x * 1e3 for x in latencies]
        print(
            f"GET /v1/jobs/{{id}} with {args.workers} of {args.workers} workers busy "
            f"({busy} still busy at the end), {len(ms)} requests from {clients} clients "
            f"on {os.cpu_count()} cores:"
        )
        print(
            f"  p50 {statistics.median(ms):.2f} ms   p90 {_percentile(ms, 0.90):.2f} ms   "
            f"p99 {_percentile(ms, 0.99):.2f} ms   max {max(ms):.2f} ms   "
            f"throughput {len(ms) / wall:.0f} req/s"
        )
        print(f"  target p99 < 50 ms: {'met' if _percentile(ms, 0.99) < 50 else 'NOT met'}")
        for i in ids:
            _request(conn, "DELETE", f"/v1/jobs/{i}")
        conn.close()
        return 0
    finally:
        server.send_signal(signal.SIGTERM)
        try:
            server.wait(20)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait(5)
        try:
            os.killpg(server.pid, signal.SIGKILL)  # anything of the server's group left over
        except ProcessLookupError:
            pass
        log.close()
        tmp.cleanup()


if __name__ == "__main__":
    sys.exit(main())

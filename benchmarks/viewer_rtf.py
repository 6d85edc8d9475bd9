"""The viewer loop's real-time factor with one headless browser connected, at the defaults,
next to the stepping-alone rate measured in the same run; with `--api-jobs N`, measured again
in the same run while the REST API (started as `make run` starts it, with its default workers)
runs N simulation jobs, and what the status readout said meanwhile.

    .venv/bin/python benchmarks/viewer_rtf.py [--seconds 15] [--api-jobs 2]

Targets (issues 7 and 19): at least 1x while streaming to the browser, stepping alone at least
5x; at least 0.8x while API jobs run (the API's worker priority and count decide that; the
viewer's part is to say "behind" when it is).
"""

from __future__ import annotations

import argparse
import json
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from collections import Counter
from pathlib import Path

from playwright.sync_api import sync_playwright

from web.app import LoopStats, ViewerApp

ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]  # fmt: skip


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _measure(app: ViewerApp, seconds: float) -> tuple[LoopStats, LoopStats, list[str]]:
    """Stats before and after `seconds` of wall time, and the status line every 0.5 s."""
    start = app.stats
    statuses: list[str] = []
    t_end = time.monotonic() + seconds
    while time.monotonic() < t_end:
        time.sleep(0.5)
        statuses.append(app.panels.shown("status"))
    return start, app.stats, statuses


def _report(title: str, seconds: float, a: LoopStats, b: LoopStats, statuses: list[str]) -> None:
    sim = b.sim_s - a.sim_s
    step = b.step_wall_s - a.step_wall_s
    print(f"{title}, {seconds:.0f} s wall at 1x:")
    print(f"  real-time factor while streaming  {sim / seconds:5.2f}x")
    print(f"  stepping alone                    {sim / max(step, 1e-9):5.2f}x")
    print(f"  frames streamed                   {(b.frames - a.frames) / seconds:5.1f} Hz")
    kinds = Counter(line.split(":")[0].split(" with")[0] for line in statuses)
    said = ", ".join(f"'{k}' {n}x" for k, n in kinds.most_common())
    print(f"  status readout (every 0.5 s)      {said}")


def _start_api(n_jobs: int, tmp: Path) -> tuple[subprocess.Popen[bytes], list[str]]:
    port = _free_port()
    cmd = [sys.executable, "-m", "sim_core.cli", "api", "--port", str(port)]
    api = subprocess.Popen(
        [*cmd, "--db", str(tmp / "bench.sqlite3")],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    base = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + 120
    while True:
        try:
            urllib.request.urlopen(f"{base}/healthz", timeout=2).read()
            break
        except OSError:
            if time.monotonic() > deadline or api.poll() is not None:
                raise SystemExit("the API did not start") from None
            time.sleep(0.5)
    ids = []
    for k in range(n_jobs):
        body = {"kind": "run", "beta": 0.66, "d31_init": [2.0 + 0.1 * k], "duration_s": 30.0}
        req = urllib.request.Request(
            f"{base}/v1/jobs",
            data=json.dumps(body).encode(),
            headers={"Content-Type": "application/json"},
            method="POST",
        )
        ids.append(json.loads(urllib.request.urlopen(req, timeout=10).read())["id"])
    return api, ids


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--seconds", type=float, default=15.0)
    ap.add_argument("--api-jobs", type=int, default=0, help="API jobs to run in a second pass")
    args = ap.parse_args()
    chromium = shutil.which("chromium")
    if chromium is None:
        raise SystemExit("needs chromium on PATH (apt-get install chromium)")
    app = ViewerApp("127.0.0.1", 0)
    app.start()
    try:
        with sync_playwright() as p, tempfile.TemporaryDirectory() as tmp:
            browser = p.chromium.launch(executable_path=chromium, args=ARGS)
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(f"http://127.0.0.1:{app.port}")
            page.get_by_text("β (simulation)").wait_for(timeout=60_000)
            _report("viewer loop, 1 browser", args.seconds, *_measure(app, args.seconds))
            if args.api_jobs > 0:
                api, _ = _start_api(args.api_jobs, Path(tmp))
                try:
                    time.sleep(3.0)  # the workers pick the jobs up
                    title = f"same, while the API runs {args.api_jobs} jobs"
                    _report(title, args.seconds, *_measure(app, args.seconds))
                finally:
                    api.terminate()
                    api.wait(timeout=30)
            browser.close()
    finally:
        app.stop()


if __name__ == "__main__":
    main()

"""The live viewer against the bench, side by side in one run: `bench`'s single simulation
(no browser; before and after the viewer, the shares against their mean), then the viewer with
one headless Chromium (software WebGL, the same cores): its real-time factor while streaming
at 1x, its stepping rate at "max" (and again with the 3D view held, its checkbox off), how
often the readouts refresh in the page, how much of the page's main thread is taken by long
tasks, the input latency of a typed beta (Enter -> applied in the simulation -> shown in the
readout, and the keystroke prefixes applied), of a slider step (key -> applied) and of a click
(Pause / Play -> applied -> the status line says so), as percentiles; per window, the animation
frames the page let through (its frame cap, web/frame_cap.py) and the CPU each process took
(the viewer, the browser's GPU process that draws WebGL in software, its renderer). With
`--frame-caps 15,10,20,0`, the stepping at "max" under each frame cap, set live in one page and
alternated. With `--api-jobs N`, the real-time factor again while the REST API runs N
simulation jobs.

    .venv/bin/python benchmarks/viewer_rtf.py [--seconds 10] [--trials 12] [--json out.json]

Targets (issue 43): input latency p95 <= 0.3 s to the simulation, clicks answered within 1 s,
readouts >= 4 Hz, the viewer's stepping >= 0.8x of bench single in the same run; at least 1x
while streaming at 1x where the machine allows (issue 7).
"""

from __future__ import annotations

import argparse
import json
import platform
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path
from typing import Any

import numpy as np
import psutil
from playwright.sync_api import Page, sync_playwright

from sim_core import RunSpec
from sim_core.numerics.bench import single_rate
from web import controls
from web.app import LoopConfig, ViewerApp
from web.entry import box_label
from web.panel_labels import DRAW_3D, PAUSE, PLAY, READ_BY_LABEL, TAG_BY_LABEL
from web.requests import SetParam, SetPlaying

ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]  # fmt: skip
BETA_BOX, BETA_READOUT = box_label(controls.BETA), "β (simulation)"
KEY_DELAY_MS = 120  # a fast typist; typed latency is measured from Enter
# Page instruments: every keydown and mousedown with its wall time (Date.now(), the clock
# Python's time.time() reads), and the main thread's long tasks (the browser's own timeline).
INSTRUMENT = """() => {
  const w = window;
  w.__keys = []; w.__clicks = []; w.__long = []; w.__seen = null;
  document.addEventListener('keydown', e => w.__keys.push([e.key, Date.now()]), true);
  document.addEventListener('mousedown', () => w.__clicks.push(Date.now()), true);
  new PerformanceObserver(l => { for (const e of l.getEntries())
    w.__long.push([performance.timeOrigin + e.startTime, e.duration]); })
    .observe({type: 'longtask'});
}"""
# Watch a readout (or the status line) every 10 ms until it satisfies `test`; the time it did.
WATCH = """([read, label, expected, mode]) => {
  const w = window; w.__seen = null;
  const get = new Function('return ' + read)();
  const status = () => document.querySelector('[data-readout=status]')?.textContent ?? '';
  const id = setInterval(() => {
    const v = label === 'status' ? status() : get(label);
    const ok = mode === 'equals' ? v === expected
             : mode === 'contains' ? v.includes(expected) : !v.includes(expected);
    if (ok) { w.__seen = Date.now(); clearInterval(id); }
  }, 10);
}"""
COUNT_CHANGES = """([read, label, ms]) => new Promise(done => {
  const get = new Function('return ' + read)();
  let last = get(label), changes = 0;
  const id = setInterval(() => {
    const v = get(label); if (v !== last) { changes++; last = v; } }, 10);
  setTimeout(() => { clearInterval(id); done(changes); }, ms);
})"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _pct(values: list[float]) -> dict[str, float | None]:
    if not values:
        return {"n": 0, "p50": None, "p95": None, "max": None}
    a = np.asarray(values)
    return {"n": len(values), "p50": float(np.percentile(a, 50)),
            "p95": float(np.percentile(a, 95)), "max": float(a.max())}  # fmt: skip


def _applied_after(app: ViewerApp, t0: float, match: Any, timeout_s: float = 30.0) -> float | None:
    """Wall time at which the first request satisfying `match` was applied after `t0`."""
    deadline = time.time() + timeout_s
    while time.time() < deadline:
        for t, req in list(app.applied):
            if t >= t0 and match(req):
                return t
        time.sleep(0.005)
    return None


def _cpu_seconds() -> dict[int, tuple[str, float]]:
    """CPU seconds so far, per process: this one ("viewer": the viewer's threads and the
    benchmark's Playwright client) and the browser's by role (the GPU process draws WebGL in
    software; the renderer runs the page)."""
    me = psutil.Process()
    out = {me.pid: ("viewer", sum(me.cpu_times()[:2]))}
    for proc in me.children(recursive=True):
        try:
            cmd = " ".join(proc.cmdline())
            if "chrom" not in cmd:
                continue
            role = "gpu" if "--type=gpu-process" in cmd else (
                "renderer" if "--type=renderer" in cmd else "browser")  # fmt: skip
            out[proc.pid] = (role, sum(proc.cpu_times()[:2]))
        except psutil.Error:
            continue
    return out


def _cores(
    a: dict[int, tuple[str, float]], b: dict[int, tuple[str, float]], wall: float
) -> dict[str, float]:
    """Cores each role took between two samples (processes alive at both)."""
    out: dict[str, float] = {}
    for pid, (role, seconds) in b.items():
        if pid in a:
            out[role] = out.get(role, 0.0) + (seconds - a[pid][1]) / wall
    return out


def _window(app: ViewerApp, page: Page, seconds: float) -> dict[str, Any]:
    """Loop stats, readout refresh rate, frames the page drew, long-task share and the CPU each
    process took (cores) over `seconds` of wall time."""
    drawn = "() => window.__igFrameCap ? window.__igFrameCap.frames : null"
    a, t0, cpu0, f0 = app.stats, time.time(), _cpu_seconds(), page.evaluate(drawn)
    changes = page.evaluate(COUNT_CHANGES, [READ_BY_LABEL, "sim time (s)", int(seconds * 1000)])
    b, t1, cpu1, f1 = app.stats, time.time(), _cpu_seconds(), page.evaluate(drawn)
    long = page.evaluate("() => window.__long")
    busy = sum(d for s, d in long if t0 * 1000 <= s <= t1 * 1000) / 1000.0
    wall = t1 - t0
    return {
        "wall_s": wall,
        "rtf": (b.sim_s - a.sim_s) / wall,
        "stepping": (b.sim_s - a.sim_s) / max(b.step_wall_s - a.step_wall_s, 1e-9),
        "frames_hz": (b.frames - a.frames) / wall,
        "drawn_hz": None if f0 is None or f1 is None else (f1 - f0) / wall,
        "cpu_cores": _cores(cpu0, cpu1, wall),
        "readout_hz": changes / wall,
        "long_task_share": busy / wall,
        "status": app.panels.shown("status"),
    }


def _frame_caps(
    app: ViewerApp, page: Page, caps: list[float], rounds: int, seconds: float
) -> list[dict[str, Any]]:
    """Stepping at "max" under each 3D frame cap, set live in the page (web/frame_cap.py),
    the caps alternated `rounds` times so that a drift of the host falls on all of them."""
    rows = []
    for _ in range(rounds):
        for cap in caps:
            page.evaluate(f"() => {{ window.__igFrameCap.fps = {cap}; }}")
            time.sleep(1.0)
            rows.append({"cap": cap, **_window(app, page, seconds)})
    return rows


def _typed_latency(app: ViewerApp, page: Page, trials: int) -> dict[str, Any]:
    """Type a beta into its box at a fast human pace and press Enter, `trials` times: Enter ->
    applied -> shown, and how many keystroke prefixes reached the simulation (should be 0)."""
    page.evaluate(TAG_BY_LABEL, [BETA_BOX, "beta"])
    box = page.locator("[data-probe-box='beta']")
    to_sim, to_page, prefixes = [], [], 0
    values = [0.64, 0.66, 0.625, 0.68, 0.635, 0.67]
    for k in range(trials):
        v = values[k % len(values)]
        text, shown = f"{v:g}", f"{v:.4f}"
        page.evaluate(WATCH, [READ_BY_LABEL, BETA_READOUT, shown, "equals"])
        box.evaluate("el => { el.focus(); el.select(); }")
        t_start = time.time()
        box.press_sequentially(text, delay=KEY_DELAY_MS)
        time.sleep(KEY_DELAY_MS / 1000.0)
        box.press("Enter")
        page.wait_for_function("window.__seen !== null", timeout=60_000)
        keys = page.evaluate("() => window.__keys")
        t_enter = [t for key, t in keys if key == "Enter"][-1] / 1000.0
        t_seen = page.evaluate("() => window.__seen") / 1000.0
        t_sim = _applied_after(app, t_start, lambda r, v=v: r == SetParam("beta", v))
        early = [r for t, r in app.applied if t >= t_start and isinstance(r, SetParam)
                 and r.name == "beta" and abs(r.value - v) > 1e-9]  # fmt: skip
        prefixes += len(early)
        if t_sim is not None:
            to_sim.append(t_sim - t_enter)
        to_page.append(t_seen - t_enter)
        page.keyboard.press("Tab")
        time.sleep(0.3)
    return {"to_simulation_s": _pct(to_sim), "to_readout_s": _pct(to_page),
            "prefixes_applied": prefixes}  # fmt: skip


def _slider_latency(app: ViewerApp, page: Page, trials: int) -> dict[str, Any]:
    """Move the beta slider one step with the keyboard (a drag's first value, which waits out
    the typing check): key -> applied in the simulation."""
    to_sim = []
    thumb = page.locator("[role=slider]").first
    thumb.focus()
    for k in range(trials):
        key = "ArrowRight" if k % 2 == 0 else "ArrowLeft"
        t_start = time.time()
        thumb.press(key)
        t_key = [t for name, t in page.evaluate("() => window.__keys") if name == key][-1] / 1e3
        t_sim = _applied_after(app, t_start, lambda r: isinstance(r, SetParam) and r.name == "beta")
        if t_sim is not None:
            to_sim.append(t_sim - t_key)
        time.sleep(0.6)  # past STREAM_S: each move is a drag's first value
    return {"to_simulation_s": _pct(to_sim)}


def _click_latency(app: ViewerApp, page: Page, trials: int) -> dict[str, Any]:
    """Click Pause, then Play, `trials` times each; until applied and until the status says."""
    to_sim, to_page = [], []
    for _ in range(trials):
        for label, playing in ((PAUSE, False), (PLAY, True)):
            mode = "contains" if not playing else "lacks"
            page.evaluate(WATCH, [READ_BY_LABEL, "status", "paused", mode])
            t_start = time.time()
            page.get_by_role("button", name=label, exact=True).click(timeout=60_000)
            page.wait_for_function("window.__seen !== null", timeout=60_000)
            t_click = page.evaluate("() => window.__clicks")[-1] / 1000.0
            t_seen = page.evaluate("() => window.__seen") / 1000.0
            t_sim = _applied_after(app, t_start, lambda r, p=playing: r == SetPlaying(p))
            if t_sim is not None:
                to_sim.append(t_sim - t_click)
            to_page.append(t_seen - t_click)
            time.sleep(0.3)
    return {"to_simulation_s": _pct(to_sim), "to_status_s": _pct(to_page)}


def _start_api(n_jobs: int, tmp: Path) -> subprocess.Popen[bytes]:
    port = _free_port()
    cmd = [sys.executable, "-m", "sim_core.cli", "api", "--port", str(port)]
    api = subprocess.Popen([*cmd, "--db", str(tmp / "bench.sqlite3")],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
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
    for k in range(n_jobs):
        body = {"kind": "run", "beta": 0.66, "d31_init": [2.0 + 0.1 * k], "duration_s": 60.0}
        req = urllib.request.Request(f"{base}/v1/jobs", data=json.dumps(body).encode(),
                                     headers={"Content-Type": "application/json"},
                                     method="POST")  # fmt: skip
        urllib.request.urlopen(req, timeout=10).read()
    return api


def _print(report: dict[str, Any]) -> None:
    b = report["bench_single_rtf"]
    print(f"host: {report['host']}")
    cap = report.get("frame_cap") or {}
    print(
        f"page: {report['query'] or 'no query'}; 3D frame cap {cap.get('fps')} a second "
        f"(0: every frame), software WebGL {cap.get('software')}"
    )
    runs = " and ".join(f"{r:.2f}x" for r in report["bench_single_runs"])
    print(f"bench single (no browser)              {b:6.2f}x real time (before and after: {runs})")
    for name in ("streaming_1x", "max_speed", "max_speed_3d_off", "api_jobs"):
        w = report.get(name)
        if w is None:
            continue
        print(f"viewer, {name:31s} rtf {w['rtf']:5.2f}x  stepping {w['stepping']:5.2f}x "
              f"({w['stepping'] / b:4.2f} of bench)  frames {w['frames_hz']:4.1f} Hz  "
              f"readouts {w['readout_hz']:4.1f} Hz  long tasks {100 * w['long_task_share']:3.0f}%"
              f" of the page's main thread")  # fmt: skip
        drawn = "-" if w["drawn_hz"] is None else f"{w['drawn_hz']:4.1f}"
        cores = "  ".join(f"{k} {v:.2f}" for k, v in sorted(w["cpu_cores"].items()))
        print(f"  animation frames (3D drawn at most) {drawn} a second; CPU cores: {cores}")
        print(f"  status: {w['status']}")
    rows = report.get("frame_caps") or []
    for cap in dict.fromkeys(r["cap"] for r in rows):
        share = [r["stepping"] / b for r in rows if r["cap"] == cap]
        drawn = np.mean([r["drawn_hz"] or 0.0 for r in rows if r["cap"] == cap])
        gpu = np.mean([r["cpu_cores"].get("gpu", 0.0) for r in rows if r["cap"] == cap])
        print(f"frame cap {cap:4g}: stepping at max {np.mean(share):4.2f} of bench "
              f"({min(share):4.2f}-{max(share):4.2f}, {len(share)} windows), drawn "
              f"{drawn:4.1f} a second, GPU process {gpu:4.2f} core")  # fmt: skip
    lats = (("typed beta", report["typed"]), ("click", report["click"]),
            ("slider key", report["slider"]))  # fmt: skip
    for name, lat in lats:
        for what, p in lat.items():
            if isinstance(p, dict):
                print(
                    f"{name:10s} {what:18s} n {p['n']:2d}  p50 {p['p50'] or 0:6.3f} s  "
                    f"p95 {p['p95'] or 0:6.3f} s  max {p['max'] or 0:6.3f} s"
                )
    print(
        f"typed prefixes applied (0.6 of 0.62 ...): {report['typed']['prefixes_applied']}"
        f" (typed at {KEY_DELAY_MS} ms a key, Enter {KEY_DELAY_MS} ms after the last)"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0, help="per measuring window")
    ap.add_argument("--trials", type=int, default=12, help="typed values; clicks: half")
    ap.add_argument("--api-jobs", type=int, default=0, help="API jobs in a last window")
    ap.add_argument("--json", type=Path, default=None, help="also write the report here")
    ap.add_argument("--shadows", action="store_true", help="the viewer casting shadows")
    ap.add_argument("--fps", type=float, default=LoopConfig.fps, help="pose stream rate")
    ap.add_argument(
        "--readout-hz",
        type=float,
        default=LoopConfig.readout_hz,
        help="how often the loop sends the readouts",
    )
    ap.add_argument("--query", default="", help="the page's URL query, e.g. fixedDpr=0.5")
    ap.add_argument(
        "--frame-caps",
        default="",
        help="also step at max under each of these 3D frame caps (e.g. 15,10,20,0; 0: every "
        "frame), set live in one page, alternated --rounds times",
    )
    ap.add_argument("--rounds", type=int, default=2, help="rounds of --frame-caps")
    args = ap.parse_args()
    chromium = shutil.which("chromium")
    if chromium is None:
        raise SystemExit("needs chromium on PATH (apt-get install chromium)")
    spec = RunSpec(beta=0.66, d31_init=2.5, duration_s=args.seconds)
    # bench single before and after the viewer, the shares against their mean: the host's
    # drift over the run's minutes falls on both sides (the two are printed)
    before, _ = single_rate(spec)
    report: dict[str, Any] = {"host": f"{platform.processor() or platform.machine()}, "
                              f"{len(__import__('os').sched_getaffinity(0))} cores"}  # fmt: skip
    app = ViewerApp(
        "127.0.0.1",
        0,
        config=LoopConfig(shadows=args.shadows, fps=args.fps, readout_hz=args.readout_hz),
    )
    report["shadows"], report["fps"], report["query"] = args.shadows, args.fps, args.query
    app.start()
    try:
        with sync_playwright() as p, tempfile.TemporaryDirectory() as tmp:
            browser = p.chromium.launch(executable_path=chromium, args=ARGS)
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(f"http://127.0.0.1:{app.port}" + (f"/?{args.query}" if args.query else ""))
            page.get_by_text(BETA_READOUT).wait_for(timeout=60_000)
            page.evaluate(INSTRUMENT)
            report["frame_cap"] = page.evaluate("() => window.__igFrameCap ?? null")
            page.wait_for_function(f"({READ_BY_LABEL})('sim time (s)') > 1.0", timeout=90_000)
            report["streaming_1x"] = _window(app, page, args.seconds)
            report["typed"] = _typed_latency(app, page, args.trials)
            report["click"] = _click_latency(app, page, max(1, args.trials // 4))
            report["slider"] = _slider_latency(app, page, args.trials)
            page.get_by_role("button", name="max", exact=True).click()
            time.sleep(1.0)
            report["max_speed"] = _window(app, page, args.seconds)
            if args.frame_caps and report["frame_cap"] is None:
                raise SystemExit("--frame-caps: the page has no frame cap (web/frame_cap.py)")
            if args.frame_caps:
                caps = [float(c) for c in args.frame_caps.split(",")]
                report["frame_caps"] = _frame_caps(app, page, caps, args.rounds, args.seconds)
                page.evaluate(
                    f"() => {{ window.__igFrameCap.fps = {report['frame_cap']['fps']}; }}"
                )
            # the 3D view held (its checkbox): what the browser's drawing costs the stepping
            page.get_by_text(DRAW_3D, exact=True).click()
            time.sleep(1.0)
            report["max_speed_3d_off"] = _window(app, page, args.seconds)
            page.get_by_text(DRAW_3D, exact=True).click()
            page.get_by_role("button", name="1x", exact=True).click()
            if args.api_jobs > 0:
                api = _start_api(args.api_jobs, Path(tmp))
                try:
                    time.sleep(3.0)
                    report["api_jobs"] = _window(app, page, args.seconds)
                finally:
                    api.terminate()
                    api.wait(timeout=30)
            browser.close()
    finally:
        app.stop()
    after, _ = single_rate(spec)
    report["bench_single_runs"] = [before, after]
    report["bench_single_rtf"] = (before + after) / 2.0
    _print(report)
    if args.json is not None:
        args.json.write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()

"""What one redraw of the Delta31 history costs the page's main thread, drawn as our SVG, as
viser's uPlot and (when plotly is installed) as viser's Plotly, side by side in one run: a bare
viser page in headless Chromium with software WebGL, 1 200 points redrawn 5 times a second for
`--seconds` each, measured with the page's own Performance.getMetrics (docs/VIEWER.md, "Why
the charts stay SVG").

    .venv/bin/python benchmarks/chart_cost.py [--seconds 10]

Plotly is not a dependency of the viewer; `pip install plotly` adds its two rows.
"""

from __future__ import annotations

import argparse
import math
import shutil
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import viser
from playwright.sync_api import sync_playwright

from web.d31_svg import d31_svg

ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader"]  # fmt: skip
N, HZ = 1200, 5.0  # the panel's cap of drawn points, and its redraw rate


def series(k: int) -> tuple[np.ndarray, np.ndarray]:
    """A Delta31 history shifted by k redraws (new numbers each time, as a walk gives)."""
    t = np.linspace(0, 60, N) + k * 0.2
    d = 2.1 + 0.3 * np.sin(t / 3) + 0.05 * np.random.default_rng(k).standard_normal(N)
    return t, d % math.tau


def panels(gui: Any) -> dict[str, tuple[Any, Callable[[int], None]]]:
    """Each way of drawing: its handle and how it redraws for the k-th data."""
    t, d = series(0)
    svg = gui.add_html(d31_svg(list(zip(t, d, strict=True)), float(t[-1]), None, "metachronal"))
    dots = {"show": True, "size": 3}
    up = gui.add_uplot(
        (t, d),
        ({"label": "t (s)"}, {"label": "Δ31", "stroke": "black", "width": 0, "points": dots}),
        scales={"x": {"time": False}, "y": {"range": (0, math.tau)}},
        aspect=2.0,
    )

    def draw_svg(k: int) -> None:
        t, d = series(k)
        svg.content = d31_svg(list(zip(t, d, strict=True)), float(t[-1]), None, "metachronal")

    def draw_uplot(k: int) -> None:
        up.data = series(k)

    out: dict[str, tuple[Any, Callable[[int], None]]] = {
        "svg": (svg, draw_svg),
        "uplot": (up, draw_uplot),
    }
    try:
        import plotly.graph_objects as go  # type: ignore[import-not-found]  # optional
    except ImportError:
        print("plotly not installed: its rows are left out (pip install plotly)")
        return out
    layout = go.Layout(height=260, margin={"l": 40, "r": 10, "t": 10, "b": 30},
                       yaxis={"range": [0, math.tau]})  # fmt: skip
    for name, trace in (("plotly (WebGL)", go.Scattergl), ("plotly (SVG)", go.Scatter)):
        handle = gui.add_plotly(go.Figure(trace(x=t, y=d, mode="markers"), layout=layout))

        def draw(k: int, handle: Any = handle, trace: Any = trace) -> None:
            t, d = series(k)
            handle.figure = go.Figure(trace(x=t, y=d, mode="markers"), layout=layout)

        out[name] = (handle, draw)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0, help="per way of drawing")
    args = ap.parse_args()
    chromium = shutil.which("chromium")
    if chromium is None:
        raise SystemExit("needs chromium on PATH (apt-get install chromium)")
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    ways = panels(server.gui)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=ARGS)
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        page.goto(f"http://127.0.0.1:{server.get_port()}")
        time.sleep(6)
        cdp = page.context.new_cdp_session(page)
        cdp.send("Performance.enable")

        def metrics() -> tuple[float, float]:
            m = {x["name"]: x["value"] for x in cdp.send("Performance.getMetrics")["metrics"]}
            return m["TaskDuration"], m["ScriptDuration"]

        for which in ["idle", *ways]:
            for name, (handle, _) in ways.items():
                handle.visible = name == which
            time.sleep(3)  # the first draw (Plotly loads its bundle) outside the window
            stop = threading.Event()

            def redraw(draw: Callable[[int], None], stop: threading.Event = stop) -> None:
                k = 0
                while not stop.is_set():
                    k += 1
                    draw(k)
                    time.sleep(1 / HZ)

            worker = None
            if which in ways:
                worker = threading.Thread(target=redraw, args=(ways[which][1],), daemon=True)
                worker.start()
            time.sleep(1)
            (task0, script0), t0 = metrics(), time.time()
            time.sleep(args.seconds)
            (task1, script1), t1 = metrics(), time.time()
            stop.set()
            if worker is not None:
                worker.join()
            n = (t1 - t0) * HZ  # redraws (for idle: 0.2 s slices)
            print(f"{which:15s} main thread busy {100 * (task1 - task0) / (t1 - t0):5.1f}%  "
                  f"per redraw: task {1000 * (task1 - task0) / n:6.1f} ms, "
                  f"script {1000 * (script1 - script0) / n:6.1f} ms")  # fmt: skip
        browser.close()
    server.stop()


if __name__ == "__main__":
    main()

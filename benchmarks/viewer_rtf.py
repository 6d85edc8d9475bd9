"""The viewer loop's real-time factor with one headless browser connected, at the defaults,
next to the stepping-alone rate measured in the same run.

    .venv/bin/python benchmarks/viewer_rtf.py [--seconds 15]

Targets (issue 7): at least 1x while streaming to the browser, stepping alone at least 5x.
"""

from __future__ import annotations

import argparse
import shutil
import time

from playwright.sync_api import sync_playwright

from web.app import ViewerApp

ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=15.0)
    args = ap.parse_args()
    chromium = shutil.which("chromium")
    if chromium is None:
        raise SystemExit("needs chromium on PATH (apt-get install chromium)")
    app = ViewerApp("127.0.0.1", 0)
    app.start()
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium, args=ARGS)
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(f"http://127.0.0.1:{app.port}")
            page.get_by_text("β (simulation)").wait_for(timeout=60_000)
            start = app.stats
            time.sleep(args.seconds)
            end = app.stats
            browser.close()
    finally:
        app.stop()
    sim = end.sim_s - start.sim_s
    step = end.step_wall_s - start.step_wall_s
    print(f"viewer loop, 1 browser, {args.seconds:.0f} s wall at 1x:")
    print(f"  real-time factor while streaming  {sim / args.seconds:5.2f}x   (target >= 1)")
    print(f"  stepping alone                    {sim / step:5.2f}x   (target >= 5)")
    fps = (end.frames - start.frames) / args.seconds
    print(f"  frames streamed                   {fps:5.1f} Hz")


if __name__ == "__main__":
    main()

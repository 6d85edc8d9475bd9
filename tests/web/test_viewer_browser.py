"""End to end: the real viewer (a subprocess) in real headless Chromium.

Under CI=true this test must run (it fails if Chromium is missing); elsewhere it skips with the
reason. The screenshot lands in docs/figures/viewer.png, which README shows.
"""

import io
import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
SHOT = ROOT / "docs" / "figures" / "viewer.png"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    # WebGL in software: without these, headless Chromium refuses WebGL and the page stays blank
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
]
READ_BY_LABEL = """label => {
  const l = [...document.querySelectorAll('label')].find(e => e.textContent.trim() === label);
  if (!l) return null;
  let node = l.parentElement;
  while (node && !node.querySelector('input:not([type=hidden])')) node = node.parentElement;
  return node ? node.querySelector('input:not([type=hidden])').value : null;
}"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture
def viewer(tmp_path: Path):
    if CHROMIUM is None:
        if os.environ.get("CI") == "true":
            pytest.fail("CI=true but no chromium on PATH: .ci/run should apt-get install it")
        pytest.skip("no chromium on PATH (apt-get install chromium); CI runs this test")
    port = _free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "sim_core.cli.main", "viewer", "--port", str(port)],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        assert proc.stdout is not None
        deadline = time.time() + 60
        url = None
        while time.time() < deadline and url is None:
            line = proc.stdout.readline()
            if line.startswith("viewer: "):
                url = line.split("viewer: ", 1)[1].strip()
            elif not line and proc.poll() is not None:
                break
        assert url, "the viewer did not print its address"
        yield url
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()


def _read(page, label: str) -> str | None:
    return page.evaluate(READ_BY_LABEL, label)


def test_page_renders_and_the_beta_slider_drives_the_simulation(viewer: str) -> None:
    from PIL import Image
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            page = browser.new_page(viewport={"width": 1400, "height": 1400})
            errors: list[str] = []
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(viewer)
            page.get_by_text("β (simulation)").wait_for(timeout=60_000)
            page.wait_for_function(f"({READ_BY_LABEL})('sim time (s)') > 0.5", timeout=60_000)

            # the 3D canvas is not blank
            canvas = page.locator("canvas").first
            img = np.asarray(Image.open(io.BytesIO(canvas.screenshot())).convert("L"), float)
            assert img.std() > 5.0, f"canvas looks blank (pixel std {img.std():.2f})"

            # the footfall diagram updates as the insect walks
            footfall = page.locator("svg[data-plot=footfall]").first
            first = footfall.get_attribute("data-t-now")
            page.wait_for_timeout(1500)
            assert footfall.get_attribute("data-t-now") != first

            # move the beta slider: the running simulation's beta follows
            assert _read(page, "β (simulation)") == "0.6600"
            slider = page.locator("[role=slider]").first
            slider.focus()
            for _ in range(4):
                slider.press("ArrowLeft")
            page.wait_for_function(
                f"({READ_BY_LABEL})('β (simulation)') === '0.6400'", timeout=20_000
            )
            SHOT.parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(SHOT))
            assert errors == [], errors
        finally:
            browser.close()

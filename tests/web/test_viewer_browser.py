"""End to end: the real viewer (a subprocess) in real headless Chromium.

Under CI=true these tests must run (they fail if Chromium is missing); elsewhere they skip with
the reason. The screenshot lands in out/viewer.png (gitignored), so `make test` leaves the tree
clean; `make screenshot` copies it to docs/figures/viewer.png, which README shows.
"""

from __future__ import annotations

import io
import os
import shutil
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from web import controls
from web.entry import box_label
from web.frame_cap import MIN_FPS, SOFTWARE_FPS, frame_cap_source
from web.panel_labels import (
    LOAD_SETTINGS,
    PRESET_METACHRONAL,
    READ_BY_LABEL,
    SUBMIT_RUN,
    TAG_BY_LABEL,
)

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
SHOT = Path(os.environ.get("VIEWER_SCREENSHOT", ROOT / "out" / "viewer.png"))
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
VIEWPORT = {"width": 1280, "height": 800}
RECT = """name => {
  const s = document.querySelector(`svg[data-plot=${name}]`);
  if (!s) return null;
  const r = s.getBoundingClientRect();
  return {x: r.x, y: r.y, width: r.width, height: r.height};
}"""
KEY_DELAY_MS = 300  # human pace: the report went wrong at 150-400 ms per key
LIVE_MS = 1000  # a typed value shows in the running simulation's readout within this


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextmanager
def running_viewer(home: Path, api_url: str) -> Iterator[str]:
    """The real viewer as a subprocess in `home`, posting jobs to `api_url`: its address once it
    prints it; stopped on exit (and said if it died meanwhile)."""
    log_path = home / "viewer.log"
    # the viewer's output goes to a file: a pipe nobody reads could fill and stall it, and the
    # file says why if it dies mid-module
    with open(log_path, "w") as log:
        proc = subprocess.Popen(
            [sys.executable, "-m", "sim_core.cli", "viewer", "--port", str(_free_port()),
             "--api-url", api_url],
            cwd=home, stdout=log, stderr=subprocess.STDOUT, text=True,
        )  # fmt: skip
    try:
        deadline = time.time() + 120
        url = None
        while time.time() < deadline and url is None and proc.poll() is None:
            for line in log_path.read_text().splitlines():
                if line.startswith("viewer: "):
                    url = line.split("viewer: ", 1)[1].strip()
            time.sleep(0.2)
        assert url, f"the viewer did not print its address:\n{log_path.read_text()[-2000:]}"
        yield url
        assert proc.poll() is None, f"the viewer died:\n{log_path.read_text()[-3000:]}"
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()


@pytest.fixture(scope="module")
def viewer(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    if CHROMIUM is None:
        if os.environ.get("CI") == "true":
            pytest.fail("CI=true but no chromium on PATH: .ci/run should apt-get install it")
        pytest.skip("no chromium on PATH (apt-get install chromium); CI runs this test")
    # an API address where nothing listens: a submit must say so (and never reach a real
    # service that a developer's `make run` keeps on :8000)
    api = f"http://127.0.0.1:{_free_port()}"
    with running_viewer(tmp_path_factory.mktemp("viewer"), api) as url:
        yield url


@pytest.fixture(scope="module")
def browser(viewer: str) -> Iterator[Any]:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            yield b
        finally:
            b.close()


def _open(browser: Any, url: str, *, draw_3d: bool = True) -> tuple[Any, list[str]]:
    page = browser.new_page(viewport=VIEWPORT)
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(url)
    page.get_by_text("β (simulation)").wait_for(timeout=60_000)
    if not draw_3d:
        # The control tests need no 3D view; software WebGL on a shared 2-core machine can
        # starve the page's input handling, so the canvas is shrunk to nothing there.
        page.add_style_tag(content="canvas { width: 1px !important; height: 1px !important; }")
    page.wait_for_function(f"({READ_BY_LABEL})('sim time (s)') > 0.5", timeout=90_000)
    return page, errors


def _type_into(page: Any, label: str, text: str) -> Any:
    """Focus the number box of control `label`, select its text, type `text` at human pace."""
    tag = label.encode().hex()
    page.evaluate(TAG_BY_LABEL, [label, tag])
    field = page.locator(f"[data-probe-box='{tag}']")
    field.evaluate("el => { el.focus(); el.select(); }")
    field.press_sequentially(text, delay=KEY_DELAY_MS)
    return field


def _read(page: Any, label: str) -> str | None:
    return page.evaluate(READ_BY_LABEL, label)


def _poll(page: Any, probe: str, test: str, arg: Any = None, timeout_ms: int = 60_000) -> Any:
    """Wait until `test` (a JavaScript expression in `v`) holds for `probe(arg)`, evaluated in
    the page at every animation frame, and return the value that passed. A page that reloads or
    redraws under load is read again instead of once: on timeout the message names the last
    value read, so a failure says what the page showed."""
    try:
        handle = page.wait_for_function(
            f"arg => {{ const v = ({probe})(arg); return ({test}) ? [v] : false; }}",
            arg=arg,
            timeout=timeout_ms,
        )
    except Exception as exc:
        raise AssertionError(f"{test} never held; last read {page.evaluate(probe, arg)!r}") from exc
    return handle.json_value()[0]


def _wait_read(page: Any, label: str, expected: str, timeout_ms: int = 60_000) -> None:
    try:
        page.wait_for_function(f"({READ_BY_LABEL})({label!r}) === {expected!r}", timeout=timeout_ms)
    except Exception as exc:  # say what was there instead
        found = _read(page, label)
        raise AssertionError(f"{label}: expected {expected!r}, read {found!r}") from exc


# Stance bars per leg in the footfall panel's window.
STANCE_BARS = """() => Object.fromEntries(['R1', 'L1', 'R2', 'L2', 'R3', 'L3'].map(leg => [leg,
  document.querySelectorAll(`svg[data-plot=footfall] rect.stance[data-leg=${leg}]`).length]))"""


def test_page_renders_a_readable_gait_and_the_slider_drives_the_simulation(
    viewer: str, browser: Any
) -> None:
    from PIL import Image

    page, errors = _open(browser, viewer)
    try:
        # the 3D canvas is not blank
        canvas = page.locator("canvas").first
        deadline = time.monotonic() + 60
        while True:  # the first frames may still be empty on a loaded host
            img = np.asarray(Image.open(io.BytesIO(canvas.screenshot())).convert("L"), float)
            if img.std() > 5.0 or time.monotonic() > deadline:
                break
            page.wait_for_timeout(500)
        assert img.std() > 5.0, f"canvas looks blank (pixel std {img.std():.2f})"

        # the footfall diagram and Delta31 are on screen at 1280x800 without scrolling
        # (read in one evaluate: the panels are redrawn a few times a second)
        footfall = page.locator("svg[data-plot=footfall]").first
        footfall.wait_for(timeout=30_000)
        page.locator("svg[data-plot=d31]").first.wait_for(timeout=30_000)
        for name in ("footfall", "d31"):
            box = page.evaluate(RECT, name)
            assert box is not None and box["height"] > 50, f"{name} plot not laid out: {box}"
            assert box["y"] >= 0 and box["y"] + box["height"] <= VIEWPORT["height"], (
                f"{name} plot not fully visible at 1280x800: {box}"
            )

        # the diagram advances, and its default window holds a few gait cycles per leg
        first = footfall.get_attribute("data-t-now")
        page.wait_for_function(
            "t => document.querySelector('svg[data-plot=footfall]')"
            ".getAttribute('data-t-now') !== t",
            arg=first,
            timeout=20_000,
        )
        page.wait_for_function(
            f"({READ_BY_LABEL})('sim time (s)') > 1.0", timeout=60_000
        )  # a full window of steps
        assert footfall.get_attribute("data-window-s") == "0.5"
        # the panel is redrawn a few times a second, after the readout: poll the bars
        _poll(page, STANCE_BARS, "Object.values(v).every(n => n >= 2 && n <= 12)")

        # move the beta slider with the keyboard: the running simulation's beta follows
        assert _read(page, "β (simulation)") == "0.6600"
        slider = page.locator("[role=slider]").first
        # the slider's own number box (which would send every keystroke) is hidden: typing
        # goes to the box under it, applied on Enter
        shown_inputs = page.evaluate(
            """label => {
              const l = [...document.querySelectorAll('label')]
                .find(e => e.textContent.trim() === label);
              let n = l.parentElement;
              while (n && !n.querySelector('[role=slider]')) n = n.parentElement;
              return [...n.querySelectorAll('input:not([type=hidden])')]
                .filter(e => e.offsetParent !== null).length;
            }""",
            "β (duty factor)",
        )
        assert shown_inputs == 0, "the beta slider shows a number box of its own"
        slider.focus()
        for _ in range(4):
            slider.press("ArrowLeft")
        _wait_read(page, "β (simulation)", "0.6400")
        slider.press("ArrowRight")
        slider.press("ArrowRight")
        slider.press("ArrowRight")
        slider.press("ArrowRight")
        _wait_read(page, "β (simulation)", "0.6600")
        page.wait_for_timeout(500)  # a fresh footfall window after the change
        # the "software WebGL" notice is about this headless browser, not the viewer
        close = page.locator(".mantine-Notification-closeButton")
        if close.count() > 0:
            close.first.click()
        page.mouse.move(400, 700)  # no hover tooltip on the slider in the picture
        # the slider's focus scrolled the panel: the picture shows the plots from the top
        page.evaluate("document.querySelector('svg[data-plot=footfall]').scrollIntoView()")
        page.wait_for_timeout(300)
        SHOT.parent.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SHOT))
        assert errors == [], errors
    finally:
        page.close()


@pytest.mark.parametrize(
    ("box", "column", "typed", "readout", "shown"),
    [
        (controls.BETA, "beta", "0.62", "β (simulation)", "0.6200"),
        (controls.BODY_MASS_G, "body_mass_g", "5.5", "body mass (simulation, g)", "5.50"),
        (controls.SLOPE_DEG, "slope_deg", "-7.5", "slope (simulation, °)", "-7.5"),
    ],
)
def test_a_value_typed_at_human_pace_applies_on_enter_and_never_a_prefix(
    viewer: str,
    browser: Any,
    box: controls.SliderRange,
    column: str,
    typed: str,
    readout: str,
    shown: str,
) -> None:
    page, errors = _open(browser, viewer, draw_3d=False)
    try:
        before = _read(page, readout)
        t_before = float(_read(page, "sim time (s)") or "nan")
        # the page's own clock: the Enter key, and the first poll (every 10 ms) at which the
        # readout shows the typed value; and every value the readout showed meanwhile
        page.evaluate(
            """([read, label, expected]) => {
              const get = new Function('return ' + read)();
              document.addEventListener('keydown', e => {
                if (e.key === 'Enter') window.__enter = Date.now(); }, true);
              window.__seen = null; window.__shown = new Set();
              const id = setInterval(() => {
                const v = get(label); window.__shown.add(v);
                if (v === expected) { window.__seen = Date.now(); clearInterval(id); }
              }, 10);
            }""",
            [READ_BY_LABEL, readout, shown],
        )
        field = _type_into(page, box_label(box), typed)  # "5.5" passes 5, "-7.5" passes -7
        # typed, not entered: nothing applied, the box keeps what was typed, a note says so
        page.wait_for_timeout(1500)
        assert _read(page, readout) == before, f"{box.label}: applied before Enter"
        assert field.input_value() == typed
        page.get_by_text(f"typed {float(typed):g}: Enter applies it").wait_for(timeout=5_000)
        field.press("Enter")
        # the readout says so within 1 s of Enter (an input reaches the walk within 0.3 s, the
        # readouts are sent 8 times a second)
        _wait_read(page, readout, shown)
        page.wait_for_function("window.__seen !== null", timeout=10_000)
        late = page.evaluate("() => window.__seen - window.__enter")
        seen = page.evaluate("() => [...window.__shown]")
        print(f"{box.label}: the readout showed {typed} {late} ms after Enter; meanwhile {seen}")
        assert late <= LIVE_MS, f"{box.label}: the readout showed {typed} {late} ms after Enter"
        assert set(seen) <= {before, shown}, f"{box.label}: the readout showed a prefix: {seen}"
        # the simulation never ran at a prefix: every touchdown since has the old or the value
        page.wait_for_timeout(1000)
        rows = [r for r in _download(page, "Δ31 trace (CSV)") if float(r["time_s"]) > t_before]
        ran = {float(r[column]) for r in rows}
        assert float(typed) in ran and ran <= {float(before or "nan"), float(typed)}, ran
        assert errors == [], errors
    finally:
        page.close()


def test_a_typed_value_applies_when_another_control_is_used_and_enter_clamps(
    viewer: str, browser: Any
) -> None:
    page, errors = _open(browser, viewer, draw_3d=False)
    try:
        before = _read(page, "β (simulation)")
        field = _type_into(page, box_label(controls.BETA), "9")
        page.wait_for_timeout(1000)
        # 9 is no duty factor: held while the person is in the box, and not overwritten
        assert _read(page, "β (simulation)") == before
        assert field.input_value() == "9"
        field.press("Enter")  # clamped to the slider's end, as the box clamps on leaving
        _wait_read(page, "β (simulation)", "0.8000")
        _wait_read(page, box_label(controls.BETA), "0.8")  # the box shows what the walk runs
        _wait_read(page, "β (duty factor)", "0.8")  # and so does the slider
        # typed without Enter, then another control used: the person left the box
        _type_into(page, box_label(controls.BETA), "0.64")
        page.wait_for_timeout(800)
        assert _read(page, "β (simulation)") == "0.8000"
        page.get_by_role("button", name="1x", exact=True).click()
        _wait_read(page, "β (simulation)", "0.6400")
        assert errors == [], errors
    finally:
        page.close()


# Pixels drawn per CSS pixel by the 3D view: the widest canvas (viser also keeps small 2D
# overlay canvases), or null before it is laid out.
CANVAS_PIXEL_RATIO = """() => {
  const wide = [...document.querySelectorAll('canvas')]
    .filter(c => c.getBoundingClientRect().width > 300);
  return wide.length ? Math.max(...wide.map(c => c.width / c.getBoundingClientRect().width))
                     : null;
}"""


def test_the_half_resolution_link_draws_the_3d_view_at_half_its_pixels(
    viewer: str, browser: Any
) -> None:
    page, errors = _open(browser, viewer)
    try:
        page.get_by_role("link", name="the 3D view at half resolution").click()
        page.wait_for_url("**fixedDpr=0.5**")
        # the reloaded page applies its resolution when its renderer starts: wait for the
        # canvas itself, not for a readout that may come first under load
        _poll(page, CANVAS_PIXEL_RATIO, "v !== null && v >= 0.45 && v <= 0.55", timeout_ms=90_000)
        assert errors == [], errors
    finally:
        page.close()


# Frames the page lets through over `ms` of its own clock (performance.now), so that a loaded
# host cannot stretch the window between two calls from Python.
FRAMES_OVER = """ms => new Promise(done => {
  const n0 = window.__igFrameCap.frames, t0 = performance.now();
  setTimeout(() => done([window.__igFrameCap.frames - n0, performance.now() - t0]), ms);
})"""


def test_a_browser_without_a_gpu_draws_the_3d_view_at_its_frame_cap(
    viewer: str, browser: Any
) -> None:
    """Headless Chromium draws WebGL in software (SwiftShader): the page caps its frames at
    SOFTWARE_FPS while poses stream at 30 Hz; `?frameCap=0` lifts the cap."""
    page, errors = _open(browser, viewer)
    try:
        chosen = page.evaluate("() => window.__igFrameCap")
        assert chosen["software"] is True and chosen["fps"] == SOFTWARE_FPS, chosen
        drawn, ms = page.evaluate(FRAMES_OVER, 3000)
        assert 1 <= drawn <= SOFTWARE_FPS * ms / 1000 + 1, f"{drawn} frames in {ms:.0f} ms"
        assert errors == [], errors
    finally:
        page.close()
    page, errors = _open(browser, viewer + "/?frameCap=0")
    try:
        assert page.evaluate("() => window.__igFrameCap.fps") == 0
        assert errors == [], errors
    finally:
        page.close()


# An animation loop on the wrapped requestAnimationFrame: its frames over `ms` of the page's
# clock, one callback beside it that throws once, and one asked for and cancelled.
WRAPPED_LOOP = """ms => new Promise(done => {
  let frames = 0, cancelledRan = false, thrown = false;
  const loop = () => { frames++; requestAnimationFrame(loop); };
  // the one that throws first: had it stopped the frame, the loop would never run
  requestAnimationFrame(() => { if (!thrown) { thrown = true; throw new Error('cb failed'); } });
  requestAnimationFrame(loop);
  cancelAnimationFrame(requestAnimationFrame(() => { cancelledRan = true; }));
  const t0 = performance.now();
  setTimeout(() => done({frames, ms: performance.now() - t0, cancelledRan}), ms);
})"""


@pytest.mark.parametrize(
    ("query", "fps"),
    [("", SOFTWARE_FPS), ("?frameCap=", SOFTWARE_FPS), ("?frameCap=%20", SOFTWARE_FPS),
     ("?frameCap=abc", SOFTWARE_FPS), ("?frameCap=-3", SOFTWARE_FPS), ("?frameCap=0", 0),
     ("?frameCap=0.2", MIN_FPS), ("?frameCap=10", 10)],
)  # fmt: skip
def test_the_frame_cap_reads_the_url_and_keeps_an_animation_loop_running(
    browser: Any, query: str, fps: float
) -> None:
    """The page's script alone, on a blank page of its own origin (no viewer): the cap it reads
    from the URL, frames at most at the cap, a callback that throws stops no other, a
    cancelled one never runs, and a second install (viser's replay) wraps nothing again."""
    page = browser.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.route(
        "http://frame-cap.test/**",
        lambda r: r.fulfill(body="<html></html>", content_type="text/html"),
    )
    try:
        page.goto("http://frame-cap.test/" + query)
        source = frame_cap_source(SOFTWARE_FPS)
        page.evaluate(f"() => {{ {source} }}")
        wrapped = page.evaluate("() => window.requestAnimationFrame")
        page.evaluate(f"() => {{ {source} }}")  # viser replays it on a reconnect
        assert page.evaluate("() => window.requestAnimationFrame") == wrapped
        cap = page.evaluate("() => window.__igFrameCap")
        assert cap["software"] is True and cap["fps"] == fps, cap
        run = page.evaluate(WRAPPED_LOOP, 1000)
        assert run["frames"] >= 1 and not run["cancelledRan"], run
        if fps > 0:
            assert run["frames"] <= fps * run["ms"] / 1000 + 1, run
        assert errors == ["cb failed"], errors  # reported, as the browser reports its own
    finally:
        page.close()


def _set_box(page: Any, label: str, text: str) -> None:
    """Type a value into the number box of control `label` and leave it (Tab)."""
    field = _type_into(page, label, text)
    field.press("Tab")
    try:
        page.wait_for_function(
            f"({READ_BY_LABEL})({label!r}) !== null && Number(({READ_BY_LABEL})({label!r})) "
            f"=== {float(text)!r}",
            timeout=10_000,
        )
    except Exception as exc:  # say what the box shows instead
        raise AssertionError(f"{label!r} shows {_read(page, label)!r}, typed {text!r}") from exc


def _run_ramp(page: Any, button: str, start: str, turn: str, hold: str, ramp: str) -> None:
    page.get_by_role("button", name=button, exact=True).click()
    # a person types once the page shows the parameter's own sweep (the click's answer); typed
    # before, the answer lands between the selection and the keys and the box reads "33"
    turn_default = controls.RAMP_DEFAULTS[controls.RAMP_BUTTONS[button]][1]
    page.wait_for_function(
        f"Number(({READ_BY_LABEL})('ramp turn')) === {turn_default!r}", timeout=30_000
    )
    for label, text in (("ramp start", start), ("ramp turn", turn), ("hold (s)", hold),
                        ("ramp (s)", ramp)):  # fmt: skip
        _set_box(page, label, text)
    page.get_by_role("button", name="max", exact=True).click()  # as fast as the machine goes
    page.get_by_role("button", name="Start ramp", exact=True).click()
    page.wait_for_function(f"({READ_BY_LABEL})('ramp') !== 'off'", timeout=30_000)


def _wait_ramp_done(page: Any, timeout_ms: int = 480_000) -> None:
    try:
        page.wait_for_function(f"({READ_BY_LABEL})('ramp') === 'off'", timeout=timeout_ms)
    except Exception as exc:  # say where the ramp and the simulation stood
        status = page.evaluate(
            "() => document.querySelector('[data-readout=status]')?.textContent ?? null"
        )
        raise AssertionError(
            f"the ramp did not end: ramp {_read(page, 'ramp')!r}, sim time "
            f"{_read(page, 'sim time (s)')!r}, {status!r}"
        ) from exc


def _download(page: Any, button: str) -> list[dict[str, str]]:
    import csv

    with page.expect_download(timeout=30_000) as info:
        page.get_by_role("button", name=button, exact=True).click()
    text = Path(info.value.path()).read_text()
    return list(csv.DictReader(io.StringIO(text)))


def test_the_delta31_export_holds_the_whole_beta_ramp(viewer: str, browser: Any) -> None:
    page, errors = _open(browser, viewer, draw_3d=False)
    try:
        page.get_by_role("button", name=PRESET_METACHRONAL, exact=True).click()
        # short (2.5 s simulated): on a loaded shared machine "max" has meant 0.05x real time
        _run_ramp(page, "ramp β", "0.66", "0.62", "0.25", "1")
        _wait_ramp_done(page)
        rows = _download(page, "Δ31 trace (CSV)")
        ramp = [r for r in rows if r["ramp"]]
        assert ramp, f"no ramp rows in {len(rows)} exported"
        t = [float(r["time_s"]) for r in ramp]
        # the whole ramp: from its first hold (0.25 s) through both legs to its last hold
        assert t[-1] - t[0] > 2.5 * 0.85, (t[0], t[-1])
        phases = [r["ramp"] for r in ramp]
        order = [p for k, p in enumerate(phases) if k == 0 or p != phases[k - 1]]
        assert order == ["beta hold", "beta down", "beta up", "beta hold"], order
        betas = [float(r["beta"]) for r in ramp]
        assert min(betas) == pytest.approx(0.62, abs=0.005) and betas[0] == pytest.approx(0.66)
        assert rows[0]["time_s"] and float(rows[0]["time_s"]) < t[0]  # the run before it, too
        # the slider was never written during the ramp; it shows the value the ramp ended at
        _poll(page, READ_BY_LABEL, "Math.abs(Number(v) - 0.66) < 1e-9", "β (duty factor)")
        assert errors == [], errors
    finally:
        page.close()


# The directions drawn in the body-mass ramp's panel, and the labels of the Delta31 marks.
RAMP_DIRECTIONS = """() => [...document.querySelectorAll(
  'svg[data-plot=ramp-path][data-param=body_mass_g] polyline[data-direction]')]
  .map(p => p.getAttribute('data-direction'))"""
D31_MARKS = """() => [...document.querySelectorAll('svg[data-plot=d31] line.mark')]
  .map(l => l.getAttribute('data-label'))"""


def test_a_body_mass_ramp_follows_hold_ramp_ramp_hold(viewer: str, browser: Any) -> None:
    page, errors = _open(browser, viewer, draw_3d=False)
    try:
        _run_ramp(page, "ramp mass", "3", "5", "0.25", "1")
        _poll(
            page,
            """label => {
              const l = [...document.querySelectorAll('label')]
                .find(e => e.textContent.trim() === label);
              let n = l.parentElement;
              while (n && !n.querySelector('[role=slider]')) n = n.parentElement;
              // the slider itself (viser 1.1.1 leaves its number box enabled; the loop
              // ignores values for the ramped parameter)
              return n.querySelector('[data-disabled], [aria-disabled=true]') !== null;
            }""",
            "v === true",
            "body mass (g)",
            timeout_ms=30_000,
        )  # the ramped parameter's slider is disabled during the ramp
        _wait_ramp_done(page)
        rows = _download(page, "ramp path (CSV)")
        assert rows and {r["ramp"] for r in rows} == {
            f"body_mass_g {p}" for p in ("hold", "up", "down")
        }
        phases = [r["ramp"].split()[-1] for r in rows]
        order = [p for k, p in enumerate(phases) if k == 0 or p != phases[k - 1]]
        assert order == ["hold", "up", "down", "hold"], order
        for r in rows:  # the mass in force at each touchdown is the schedule's, within a chunk
            assert float(r["body_mass_g"]) == pytest.approx(float(r["scheduled"]), abs=0.05), r
        masses = [float(r["body_mass_g"]) for r in rows]
        assert max(masses) == pytest.approx(5.0, abs=0.15) and masses[-1] == pytest.approx(3.0)
        _wait_read(page, "body mass (simulation, g)", "3.00")
        # the ramp's own panel: Delta31 against the mass, both directions drawn; the history
        # marked at each phase; the button group names the parameter it drives
        plot = page.locator("svg[data-plot=ramp-path][data-param=body_mass_g]")
        plot.wait_for(timeout=30_000)
        _poll(page, RAMP_DIRECTIONS, "v.includes('up') && v.includes('down')")
        _poll(page, D31_MARKS, "v.includes('ramp mass up') && v.includes('ramp over')")
        page.get_by_text("ramp drives — body mass (g)").wait_for(timeout=10_000)
        assert errors == [], errors
    finally:
        page.close()


def _load(page: Any, path: Path) -> None:
    with page.expect_file_chooser(timeout=30_000) as chooser:
        page.get_by_role("button", name=LOAD_SETTINGS, exact=True).click()
    chooser.value.set_files(str(path))


def test_a_submit_says_where_the_job_went_and_settings_load_back(
    viewer: str, browser: Any, tmp_path: Path
) -> None:
    import json

    page, errors = _open(browser, viewer, draw_3d=False)
    try:
        # the viewer posts the job itself; with no API at its address it says so, in words
        page.get_by_role("button", name=SUBMIT_RUN, exact=True).click()
        status = page.locator("[data-job-status=unreachable]")
        status.wait_for(timeout=30_000)
        assert "refused" in status.inner_text().lower()

        # the exported settings, edited, load back: the walk restarts where the file says
        page.get_by_role("button", name="1x", exact=True).click()
        page.get_by_text("speed — 1x").wait_for(timeout=10_000)
        with page.expect_download(timeout=30_000) as info:
            page.get_by_role("button", name="settings (JSON)", exact=True).click()
        original = Path(info.value.path()).read_bytes()
        assert json.loads(original)["params"] == {}  # the defaults, said so
        _wait_read(page, "model", "defaults")
        edited = json.loads(original) | {"beta": 0.62, "body_mass_g": 4.5, "slope_deg": -5.0,
                                         "speed": "max", "ground": "penalty",
                                         "params": {"kp_lift": 0.001}}  # fmt: skip
        (tmp_path / "edited.json").write_text(json.dumps(edited))
        _load(page, tmp_path / "edited.json")
        _wait_read(page, "β (simulation)", "0.6200")
        _wait_read(page, "body mass (simulation, g)", "4.50")
        _wait_read(page, "slope (simulation, °)", "-5.0")
        _wait_read(page, "ground", "penalty")
        _wait_read(page, "model", "kp_lift 0.001")  # a non-default parameter is shown
        page.get_by_text("speed — max").wait_for(timeout=10_000)
        # ... and kept across a ground switch, and in the job bodies offered
        page.get_by_role("button", name="constraint", exact=True).click()
        _wait_read(page, "ground", "constraint")
        assert _read(page, "model") == "kp_lift 0.001"
        _poll(page, "() => document.querySelector('pre[data-job=run]')?.textContent ?? ''",
              "v.includes('\"kp_lift\": 0.001') && v.includes('\"constraint\"')")  # fmt: skip
        # a file out of the controls' range is refused, naming the field; nothing changes
        (tmp_path / "bad.json").write_text(json.dumps(edited | {"beta": 0.9}))
        _load(page, tmp_path / "bad.json")
        note = page.locator("[data-note]").filter(has_text="not loaded")
        note.wait_for(timeout=30_000)
        assert "beta: 0.9 is outside 0.55..0.8" in note.inner_text()
        assert _read(page, "β (simulation)") == "0.6200"
        # and the original file puts everything back
        (tmp_path / "original.json").write_bytes(original)
        _load(page, tmp_path / "original.json")
        _wait_read(page, "ground", "constraint")
        _wait_read(page, "model", "defaults")
        _wait_read(page, "body mass (simulation, g)", f"{json.loads(original)['body_mass_g']:.2f}")
        page.get_by_text("speed — 1x").wait_for(timeout=10_000)
        assert errors == [], errors
    finally:
        page.close()

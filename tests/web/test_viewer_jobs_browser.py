"""End to end: a run job submitted from the viewer in headless Chromium to a real API is
listed with its state, then replayed in the Delta31 and footfall panels, labelled as the
job's, and the live walk comes back (docs/VIEWER.md, "Jobs from this viewer")."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.web.test_viewer_browser import (
    ARGS,
    CHROMIUM,
    _open,
    _poll,
    _set_box,
    running_viewer,
)
from web.panel_labels import LIVE_AGAIN, SUBMIT_RUN

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "server"))
from api_harness import Server, free_port  # the server tests' harness

pytestmark = pytest.mark.browser
ROW = "() => [...document.querySelectorAll('[data-job-row]')].map(e => e.dataset.state)"
REPLAYED = """() => ['d31', 'footfall'].map(p => {
  const s = document.querySelector(`svg[data-plot=${p}]`);
  const h = s && s.parentElement.querySelector('[data-replay]');
  return h ? h.dataset.replay : null;
})"""


@pytest.fixture(scope="module")
def viewer_and_api(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    if CHROMIUM is None:
        pytest.skip("no chromium on PATH (apt-get install chromium); CI runs this test")
    home = tmp_path_factory.mktemp("jobs")
    env = {"INSECT_GAIT_WORKERS": "1", "INSECT_GAIT_LOG_LEVEL": "warning"}
    api = Server(db=home / "jobs.sqlite3", port=free_port(), env=env, log=home / "api.log")
    api.start(timeout=60)
    try:
        with running_viewer(home, api.url) as url:
            yield url
    finally:
        api.stop()


def test_a_submitted_run_job_is_listed_and_replays_in_the_panels(viewer_and_api: str) -> None:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            page, errors = _open(browser, viewer_and_api, draw_3d=False)
            _set_box(page, "job duration (s)", "1")
            page.get_by_role("button", name=SUBMIT_RUN, exact=True).click()
            _poll(page, ROW, "v.length === 1 && v[0] === 'done'", timeout_ms=180_000)
            job_id = page.locator("[data-job-row]").first.get_attribute("data-job-id") or ""
            replay = page.get_by_role("button", name=f"Replay job {job_id[:8]} in the panels")
            replay.click()
            _poll(page, REPLAYED, f"v[0] === '{job_id}' && v[1] === '{job_id}'")
            assert "not the live walk" in page.locator("[data-replay]").first.inner_text()
            page.get_by_role("button", name=LIVE_AGAIN, exact=True).click()
            _poll(page, REPLAYED, "v[0] === null && v[1] === null")
            assert errors == [], errors
        finally:
            browser.close()

"""The API's docs pages in a real browser ask nothing of the internet.

The service runs in labs without internet: Swagger UI and ReDoc are served from the installed
package, and a page that still reaches out (ReDoc's bundle fetched its "by Redocly" logo from
cdn.redoc.ly; Swagger UI's validator badge calls validator.swagger.io for non-local hosts)
either hangs on a blocked network or leaks the spec's address.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable
from urllib.parse import urlsplit

import pytest
from api_harness import Server

pytestmark = pytest.mark.browser
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"]


@pytest.mark.parametrize(("page", "ready"), [("/redoc", "redoc-wrap"), ("/docs", "swagger-ui")])
def test_docs_pages_load_nothing_from_elsewhere(
    make_server: Callable[..., Server], page: str, ready: str
) -> None:
    if CHROMIUM is None:
        if os.environ.get("CI") == "true":
            pytest.fail("CI=true but no chromium on PATH: .ci/run should apt-get install it")
        pytest.skip("no chromium on PATH (apt-get install chromium); CI runs this test")
    from playwright.sync_api import sync_playwright

    srv = make_server(workers=0)
    asked: list[str] = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            tab = browser.new_page()
            tab.on("request", lambda r: asked.append(r.url))
            tab.goto(srv.url + page)
            tab.wait_for_selector(f".{ready}", timeout=30_000)
            tab.wait_for_load_state("networkidle", timeout=30_000)
            # the page drew the API, not an error
            assert "insect-gait API" in tab.content()
        finally:
            browser.close()
    here = urlsplit(srv.url).netloc
    elsewhere = [
        u for u in asked if not u.startswith(("data:", "blob:")) and urlsplit(u).netloc != here
    ]  # a blob: is the page's own worker
    assert not elsewhere, elsewhere

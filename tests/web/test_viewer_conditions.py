"""End to end: the bifurcation and drift-surface panels follow the walk's ground and mass.

The real viewer in headless Chromium (the fixtures of tests/web/test_viewer_browser.py): on the
paper's ground (`penalty`) both panels name it in their titles; the surface panel draws
`surface_penalty.json` (what `reproduce` writes for that ground) and the bifurcation panel says
its finder results are of another ground; at 6 g there is no surface, the panel says so, offers
to compute one and draws no live point. Every read waits in the page for what it asserts.
"""

from __future__ import annotations

from typing import Any

import pytest

from tests.web.test_viewer_browser import _open, _poll, _type_into, _wait_read, browser, viewer
from web import controls
from web.conditions import Conditions, ground_words
from web.entry import box_label
from web.panel_labels import COMPUTE_SURFACE

pytestmark = pytest.mark.browser
__all__ = ["browser", "viewer"]  # the fixtures, imported to be used here

# what a panel shows: its title (its lines joined), its note (whole, from the tooltip), how many
# live points it draws and how many surface cells
PANEL = """name => {
  const s = document.querySelector(`svg[data-plot=${name}]`);
  if (!s) return null;
  const lines = el => el ? Array.from(el.querySelectorAll('tspan')).map(t => t.textContent)
    .join(' ') : '';
  const note = s.querySelector('text.note > title');
  return {title: lines(s.querySelector('text.title')), note: note ? note.textContent : '',
          live: s.querySelectorAll('circle.live').length,
          cells: Number(s.getAttribute('data-n-cells') || 0)};
}"""
# frames, since it is installed, in which the surface panel draws a live point under a title
# that does not name the ground `words` (checked at every animation frame, not once)
WATCH = """words => {
  window.__wrong = 0;
  const tick = () => {
    const s = document.querySelector('svg[data-plot=surface]');
    const title = s ? Array.from(s.querySelectorAll('text.title tspan'))
      .map(t => t.textContent).join(' ') : '';
    if (s && s.querySelector('circle.live') && !title.includes(words)) window.__wrong += 1;
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
}"""


def _panels_name(page: Any, want: Conditions) -> dict[str, Any]:
    """Wait until both panels' titles end with `want`'s conditions; what they show then."""
    label = want.label()
    test = f"v && v.title.endsWith({('— ' + label)!r})"
    return {name: _poll(page, PANEL, test, name) for name in ("bifurcation", "surface")}


def test_the_panels_name_and_follow_the_paper_ground_and_6_g(viewer: str, browser: Any) -> None:
    page, errors = _open(browser, viewer, draw_3d=False)
    try:
        paper = controls.GROUND_LABEL["penalty"]
        page.get_by_role("button", name=paper, exact=True).click()
        _wait_read(page, "ground", paper)
        shown = _panels_name(page, Conditions("penalty", 3.0, 0.0))
        # reproduce's surface on the paper's ground is drawn; the finder's file is not its own
        assert shown["surface"]["cells"] > 0 and shown["surface"]["note"] == "", shown
        assert "no finder results for" in shown["bifurcation"]["note"], shown

        # from here on the walk is on the paper's ground: no frame may draw its live point
        # over a surface whose title names another
        page.evaluate(WATCH, ground_words("penalty"))
        field = _type_into(page, box_label(controls.BODY_MASS_G), "6")
        field.press("Enter")
        _wait_read(page, "body mass (simulation, g)", "6.00")
        six = Conditions("penalty", 6.0, 0.0)
        shown = _panels_name(page, six)
        surface = _poll(page, PANEL, "v && v.note.startsWith('no drift surface for')", "surface")
        assert six.label() in surface["note"] and COMPUTE_SURFACE in surface["note"], surface
        assert surface["cells"] == 0 and surface["live"] == 0, surface
        page.get_by_role("button", name=COMPUTE_SURFACE, exact=True).wait_for(timeout=30_000)
        assert "no finder results for" in shown["bifurcation"]["note"], shown
        assert page.evaluate("window.__wrong") == 0
        assert errors == [], errors
    finally:
        page.close()

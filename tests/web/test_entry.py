"""A live parameter's two controls, without a browser: the slider streams, the box waits for Enter.

The browser half (a real Chromium typing at human pace, the Delta31 export showing no prefix,
the slider's own box hidden) is tests/web/test_viewer_browser.py; this drives the callbacks of
real viser handles on a real (unconnected) viser server, as viser calls them for a browser.
"""

from collections.abc import Iterator
from types import SimpleNamespace

import pytest
import viser

from web import controls
from web.entry import EntryGate, LiveSlider, box_label, hide_slider_box_css, watch_controls

PERSON = SimpleNamespace(client=object())  # a GuiEvent's only field these callbacks read


@pytest.fixture(scope="module")
def server() -> Iterator[viser.ViserServer]:
    s = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield s
    finally:
        s.stop()


def _live(server: viser.ViserServer, spec: controls.SliderRange) -> tuple[LiveSlider, list]:
    applied: list[float] = []
    return LiveSlider(server, spec, applied.append), applied


def _type(live: LiveSlider, value: float) -> None:
    live.box.value = value  # type: ignore[misc]
    live._on_typed(PERSON)  # type: ignore[arg-type]


def _drag(live: LiveSlider, value: float) -> None:
    live.slider.value = value  # type: ignore[misc]
    live._on_drag(PERSON)  # type: ignore[arg-type]


def test_a_keystroke_is_held_and_enter_applies_it_clamped(server: viser.ViserServer) -> None:
    live, applied = _live(server, controls.BETA)
    for prefix in (0.0, 0.6, 0.62):  # "0.62" as a number box sends it
        _type(live, prefix)
    assert applied == [] and live.gate.typing and live.note.visible
    live.commit()  # Enter
    assert applied == [0.62] and not live.gate.typing and not live.note.visible
    assert live.value == live.box.value == 0.62  # the slider follows the box
    _type(live, 9.0)
    live.commit()
    assert applied[-1] == controls.BETA.hi and live.box.value == controls.BETA.hi
    live.commit()  # Enter again with nothing typed: nothing new applied
    assert len(applied) == 2


def test_a_drag_streams_from_its_first_value_and_drops_a_held_one(
    server: viser.ViserServer,
) -> None:
    live, applied = _live(server, controls.BODY_MASS_G)
    _drag(live, 3.5)
    _drag(live, 3.6)
    assert applied == [3.5, 3.6] and live.box.value == 3.6  # at once; the box follows
    _type(live, 5.0)
    _drag(live, 3.7)  # the person chose the slider instead of Enter
    assert applied == [3.5, 3.6, 3.7] and not live.gate.typing and not live.note.visible
    live.commit()
    assert applied == [3.5, 3.6, 3.7]


def test_the_loops_own_writes_are_not_a_persons_values(server: viser.ViserServer) -> None:
    live, applied = _live(server, controls.SLOPE_DEG)
    live.show(5.0)  # a ramp's start, a loaded file: viser calls back with no client
    assert applied == [] and live.value == live.box.value == 5.0
    live.disabled = True
    assert live.slider.disabled and live.box.disabled
    live.disabled = False


def test_another_control_applies_what_waits_in_a_box(server: viser.ViserServer) -> None:
    beta, beta_applied = _live(server, controls.BETA)
    mass, mass_applied = _live(server, controls.BODY_MASS_G)
    assert watch_controls(server, [beta, mass])
    _type(beta, 0.64)
    mass.leave()  # mass's own controls used: nothing of mass waits
    assert mass_applied == [] and beta.gate.typing
    beta.leave()  # the hook calls this for every control not beta's own
    assert beta_applied == [0.64] and beta.box.value == 0.64


def test_the_gate_and_the_markup() -> None:
    gate = EntryGate()
    assert gate.commit() is None and not gate.drop()
    gate.typed(1.0)
    gate.typed(1.5)
    assert gate.typing and gate.commit() == 1.5 and not gate.typing
    assert box_label(controls.BETA) == "β ↵"  # short: it sits under the slider that names it
    assert '[id="ab-1"] ~ *' in hide_slider_box_css("ab-1")

"""The live sliders' rule, without a browser: a drag streams, a typed number waits for Enter.

The browser half (a real Chromium typing at human pace, the Delta31 export showing no prefix)
is tests/web/test_viewer_browser.py; this pins the rule itself with a hand-driven clock.
"""

import pytest

from web.entry import (
    GRACE_INITIAL_S,
    GRACE_MAX_S,
    GRACE_MIN_S,
    STREAM_S,
    DirtyLag,
    EntryGate,
)


class Clock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_a_drag_waits_out_the_grace_once_then_streams() -> None:
    clock = Clock()
    gate = EntryGate(clock=clock)
    assert gate.changed(0.64) == "wait"
    clock.t += 0.05
    assert gate.changed(0.645) == "held-for-timer"  # the waiting timer takes the latest
    clock.t += GRACE_INITIAL_S
    assert gate.due() == 0.645
    clock.t += 0.05
    assert gate.changed(0.65) == "apply"  # the same drag: at once
    clock.t += STREAM_S + 0.01
    assert gate.changed(0.66) == "wait"  # a pause: the next move waits again


def test_typing_holds_every_keystroke_until_enter() -> None:
    clock = Clock()
    gate = EntryGate(clock=clock)
    assert gate.changed(5.0) == "wait"  # "5" of "5.5": its dirty is still on the way
    clock.t += 0.13
    gate.typed()
    assert gate.due() is None  # the timer finds a keystroke: nothing to apply
    assert gate.held == 5.0
    assert gate.changed(5.5) == "hold"
    assert gate.commit() == 5.5 and not gate.typing
    assert gate.commit() is None  # nothing typed since
    assert gate.changed(5.6) == "wait"  # after Enter a drag is a drag again


def test_the_grace_follows_how_late_this_browser_says_it_types() -> None:
    clock = Clock()
    lag = DirtyLag()
    gate = EntryGate(lag, clock)
    assert lag.grace_s() == GRACE_INITIAL_S
    gate.changed(0.6)
    clock.t += 0.15
    gate.typed()
    assert lag.grace_s() == pytest.approx(2 * 0.15)
    gate.typed()  # said again (the mark was cleared meanwhile): not a second lag
    assert lag.grace_s() == pytest.approx(2 * 0.15)
    gate.commit()
    # a dirty so late that the keystroke was applied as a drag: still learnt
    clock.t += 5.0
    gate.changed(0.7)
    clock.t += GRACE_INITIAL_S
    assert gate.due() == 0.7
    clock.t += 0.1
    gate.typed()
    assert lag.grace_s() == GRACE_MAX_S  # 2 x 0.4 s, capped
    assert GRACE_MIN_S <= DirtyLag().grace_s() <= GRACE_MAX_S


def test_a_quick_browser_still_gets_the_minimum_grace() -> None:
    clock = Clock()
    lag = DirtyLag()
    gate = EntryGate(lag, clock)
    gate.changed(1.0)
    clock.t += 0.01
    gate.typed()
    assert lag.grace_s() == GRACE_MIN_S

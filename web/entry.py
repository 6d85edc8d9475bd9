"""A live slider whose drag streams and whose typed number waits for Enter.

A viser slider sends its number box's every keystroke as a new value, exactly as it sends a
drag: typing "5.5" into the body mass box used to run the walk at 5 g before 5.5 g, and on a
model with a fold near beta 0.6475 a typed prefix is an uncontrolled perturbation. The two are
told apart by viser's form: each live slider sits in its own (unlabelled) form, and a browser
tells the server the first time a person types into a form's box since its last submit (the
form's "dirty" signal, from the native input event that a drag never fires). So:

- a value that arrives while the box is being typed into is held; Enter (the form's submit)
  applies the last one, clamped to the slider's range as the box itself clamps it;
- a held value is also applied when the person uses any other control (they left the box);
- a value that arrives with no typing is a drag or a click on the track: it is applied once
  a grace has passed with no "dirty" (as long as this browser has been taking to send it:
  `DirtyLag`), and the values that follow it within `STREAM_S` are applied at once;
- a value taken as a drag clears the browser's dirty mark, so that a keystroke whose "dirty"
  was lost in viser's message throttle is announced again by the next one.

viser 1.1 gives the dirty signal to its browsers only, so `watch_forms` registers one more
handler for it (and one for any control's update): the only place the viewer reaches past
viser's public API, which is why pyproject pins viser to 1.1.
"""

from __future__ import annotations

import functools
import logging
import math
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any, Literal

import viser

from web.controls import SliderRange

log = logging.getLogger(__name__)

# How long a value with no typing behind it waits before it is applied as a drag: as long as
# this browser takes to say that a box is being typed into. It sends the form's first "dirty"
# through viser's 50 ms message throttle, whose timer a page busy drawing the 3D walk in software
# runs late: measured from the keystroke's value to the dirty at the server, 0.13-0.16 s on a
# quiet page and 0.25-0.34 s with the 3D view live, on a 2-core host. So the wait is learnt
# (`DirtyLag`): twice the slowest of the last 8 lags, within these bounds; a drag's first
# value is that late, the values after it are not.
GRACE_INITIAL_S = 0.3
GRACE_MIN_S, GRACE_MAX_S = 0.2, 0.6
GRACE_FACTOR = 2.0
# A drag sends a value every 50 ms while the pointer moves: values this close to the previous
# applied one belong to the same drag and are applied at once.
STREAM_S = 0.3
# A "dirty" this soon after a value was applied as a drag came too late for it: that value was
# a keystroke, and the lag is learnt all the same.
LATE_DIRTY_S = 1.0


class DirtyLag:
    """How late this viewer's browsers announce typing: the grace a drag's first value waits."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._lags: deque[float] = deque(maxlen=8)

    def add(self, lag_s: float) -> None:
        with self._lock:
            self._lags.append(lag_s)

    def grace_s(self) -> float:
        with self._lock:
            if not self._lags:
                return GRACE_INITIAL_S
            return min(GRACE_MAX_S, max(GRACE_MIN_S, GRACE_FACTOR * max(self._lags)))


# What `EntryGate.changed` says to do with a value: apply it now, start the grace's timer, hold
# it for Enter, or leave it to the timer already running (which takes the latest value).
Verdict = Literal["apply", "wait", "hold", "held-for-timer"]


class EntryGate:
    """The rule above for one slider, with no GUI: what to apply, hold or wait out.

    Callbacks arrive on viser's thread pool and event loop, so every method takes the lock.
    """

    def __init__(
        self, lag: DirtyLag | None = None, clock: Callable[[], float] = time.monotonic
    ) -> None:
        self.lag = DirtyLag() if lag is None else lag
        self._clock = clock
        self._lock = threading.Lock()
        self._waited_at = -math.inf  # when the latest 'wait' began
        self.typing = False  # a person is typing into the box (dirty since the last submit)
        self.held: float | None = None  # the box's latest typed value, waiting for Enter
        self._pending: float | None = None  # a value waiting out the grace
        self._stream_until = -math.inf  # values before this belong to a drag being applied

    def changed(self, value: float) -> Verdict:
        """A value arrived: 'apply' it now, 'wait' (call `due` after `lag.grace_s()`), 'hold'
        it for Enter, or 'held-for-timer' (a timer already waits and takes this latest one)."""
        with self._lock:
            now = self._clock()
            if self.typing:
                self.held = value
                return "hold"
            if self._pending is not None:
                self._pending = value  # a timer already waits: it takes the latest
                return "held-for-timer"
            if now < self._stream_until:
                self._stream_until = now + STREAM_S
                return "apply"
            self._pending = value
            self._waited_at = now
            return "wait"

    def due(self) -> float | None:
        """The grace after a 'wait': the value to apply as a drag, or None if typing began."""
        with self._lock:
            value, self._pending = self._pending, None
            if value is None or self.typing:
                return None
            self._stream_until = self._clock() + STREAM_S
            return value

    def typed(self) -> None:
        """The browser says the box is being typed into: what waits is a keystroke, held."""
        with self._lock:
            now = self._clock()
            lag = now - self._waited_at
            if not self.typing and (self._pending is not None or lag < LATE_DIRTY_S):
                self.lag.add(lag)  # the first keystroke's value waited (or leaked) this long
            log.debug("typing, %.3f s after the first value", lag)
            self.typing = True
            self._stream_until = -math.inf
            if self._pending is not None:
                self.held, self._pending = self._pending, None

    def commit(self) -> float | None:
        """Enter, or the person moved on: the held value (None if nothing was typed)."""
        with self._lock:
            value, self.held = self.held, None
            self.typing = False
            return value


class LiveSlider:
    """A slider in its own form, with a note under it while a typed value waits for Enter.

    `apply(value)` is called with each value to apply, already inside the slider's range.
    """

    def __init__(
        self,
        server: viser.ViserServer,
        spec: SliderRange,
        apply: Callable[[float], None],
        lag: DirtyLag | None = None,
    ) -> None:
        self.spec = spec
        self._apply = apply
        self.gate = EntryGate(lag)
        label = f"{spec.label} ({spec.unit})" if spec.unit else spec.label
        gui = server.gui
        with gui.add_form(None) as self.form:
            self.slider = gui.add_slider(
                label, min=spec.lo, max=spec.hi, step=spec.step, initial_value=spec.initial
            )
            self.note = gui.add_html("", visible=False)
        self.slider.on_update(self._on_update)
        self.form.on_submit(lambda _event: self.commit())
        # set by `watch_forms`: clear the browsers' dirty mark (so the next keystroke announces
        # itself again), and show a value in the box even where the server thinks it is there
        self.rearm: Callable[[], None] = lambda: None
        self.echo: Callable[[float], None] = self._set_value

    def _set_value(self, value: float) -> None:
        self.slider.value = value  # type: ignore[misc]  # viser types the setter on a subclass

    def _on_update(self, event: viser.GuiEvent) -> None:
        if event.client is None:
            return  # the loop set this slider itself: not a person's request
        value = float(self.slider.value)
        verdict = self.gate.changed(value)
        log.debug("%s: %r -> %s", self.spec.label, value, verdict)
        if verdict != "hold":
            # viser's browser sends messages through one throttle in which the latest message
            # wins: a keystroke's value can overwrite the form's "dirty" before it is sent (a
            # busy page delays the throttle's timer), and the browser then never sends it again.
            # Clearing its dirty mark after every value taken as a drag lets the next keystroke
            # announce the typing: a lost signal costs one prefix, not all of them.
            self.rearm()
        if verdict == "apply":
            self._apply_typed(value)
        elif verdict == "wait":
            timer = threading.Timer(self.gate.lag.grace_s(), self._after_grace)
            timer.daemon = True
            timer.start()
        elif verdict == "hold":
            self._show_note(value)

    def _after_grace(self) -> None:
        value = self.gate.due()
        if value is not None:
            self._apply_typed(value)
        elif self.gate.held is not None:
            self._show_note(self.gate.held)

    def _apply_typed(self, value: float) -> None:
        """A streamed value: one outside the range is a keystroke whose 'dirty' never came."""
        v = self.spec.typed(value)
        if v is not None:
            self._apply(v)

    def commit(self) -> None:
        """Enter: apply what the box holds, clamped as the box clamps it; NaN (empty) is not."""
        was_typing = self.gate.typing
        value = self.gate.commit()
        self._show_note(None)
        if value is None and was_typing:
            # typed, but no value reached the server (the throttle dropped it): the box shows
            # what the walk runs, so the person sees that the number did not arrive
            self.echo(float(self.slider.value))
        elif value is not None and math.isfinite(value):
            v = self.spec.clamp(value)
            self._apply(v)
            # the box shows what was applied: clamped, and, where the throttle above dropped the
            # last keystroke's value for the submit, the value the server had (not silently a
            # different number in the box than in the walk)
            self.echo(v)

    def leave(self) -> None:
        """Another control was used: a typed value waiting here is applied (the form is
        submitted from the server, which also clears the browser's dirty mark)."""
        if self.gate.typing:
            self.form.submit()

    def _show_note(self, value: float | None) -> None:
        if value is None:
            self.note.visible = False
            return
        text = f"{value:g}" if math.isfinite(value) else "nothing"
        self.note.content = (
            f'<div style="font-size:0.75em;color:#a15c00;padding-left:0.5em">'
            f"typed {text}: Enter applies it</div>"
        )
        self.note.visible = True


def watch_forms(server: viser.ViserServer, live: list[LiveSlider]) -> bool:
    """Route viser's form 'dirty' signal and every control's update to the live sliders.

    Returns False (and logs why) if this viser has no such messages: the sliders then apply
    typed prefixes as a drag's values, as before, and the viewer still works.
    """
    try:
        from viser import _messages as messages

        interface: Any = server.gui._websock_interface  # viser 1.1: no public hook for these
        dirty, update = messages.GuiFormDirtyMessage, messages.GuiUpdateMessage
        submit = messages.GuiFormSubmitMessage
    except (ImportError, AttributeError) as exc:
        log.warning("typed values apply per keystroke: this viser has no form signal (%s)", exc)
        return False
    by_form = {s.form._impl.uuid: s for s in live}  # viser 1.1: handles show no public id
    by_slider = {s.slider._impl.uuid: s for s in live}

    def on_dirty(_client: Any, message: Any) -> None:
        target = by_form.get(message.uuid)
        if target is not None:
            target.gate.typed()

    def on_update(_client: Any, message: Any) -> None:
        for s in live:
            if by_slider.get(message.uuid) is not s:
                s.leave()

    for s in live:
        form_id, slider_id = s.form._impl.uuid, s.slider._impl.uuid
        s.rearm = functools.partial(interface.queue_message, submit(uuid=form_id))
        s.echo = functools.partial(_echo, interface, update, s, slider_id)
    interface.register_handler(dirty, on_dirty)
    interface.register_handler(update, on_update)
    return True


def _echo(interface: Any, update: Any, live: LiveSlider, uuid: str, value: float) -> None:
    """Set the slider and send its value to the browsers even if the server holds it already
    (viser's setter sends nothing then, but the box may show a keystroke the server never got)."""
    live.slider.value = value  # type: ignore[misc]  # viser types the setter on a subclass
    interface.queue_message(update(uuid, {"value": value}))

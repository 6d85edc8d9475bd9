"""A live parameter as two controls: a slider that streams, and a number box applied on Enter.

viser's slider has a number box of its own, and it sends that box's every keystroke as a new
value exactly as it sends a drag: typing "5.5" into the body mass box ran the walk at 5 g before
5.5 g, and on a model with a fold near beta 0.6475 a typed prefix is an uncontrolled
perturbation. Telling a keystroke from a drag after the fact needs the browser's "dirty" signal,
which viser 1.1 sends through the same lossy 50 ms throttle as the values and 0.13-0.34 s late,
so every drag's first value had to wait that long (0.58 s measured with the 3D walk live).

So the two are separate controls and need no telling apart:
- the slider (its own number box hidden by a style rule) streams: every value is applied as it
  comes, a drag's first one too;
- the number box under it, in its own unlabelled viser form, never applies a keystroke: it holds
  the latest typed value, and Enter (the form's submit) applies it, clamped to the slider's range
  as the box clamps it; so does using any other control (the person left the box). A drag of
  this parameter's slider drops a held value: the person chose the slider instead;
- both show the value in force: a drag writes the box, Enter writes the slider.

"Any other control" and the box's forced echo need one hook past viser's public API
(`watch_controls`, through web/viser_private.py), which is why pyproject pins viser to 1.1;
without it the box still applies on Enter.
"""

from __future__ import annotations

import functools
import logging
import math
import threading
from collections.abc import Callable
from typing import Any

import viser

from web.controls import SliderRange
from web.viser_private import NoHook, private_channel

log = logging.getLogger(__name__)

BOX_SUFFIX = "↵"  # the typed box's label: the slider's, and the key that applies it
BOX_HINT = "Type a value and press Enter: it applies then, never per keystroke."


def slider_label(spec: SliderRange) -> str:
    """The label of a live parameter's slider: its words and unit."""
    return f"{spec.label} ({spec.unit})" if spec.unit else spec.label


def box_label(spec: SliderRange) -> str:
    """The label of a live parameter's typed box, under its slider: the parameter's first words
    ("β", "body mass") and the key that applies it; the browser tests type into it by label."""
    return f"{spec.label.split(' (')[0]} {BOX_SUFFIX}"


def hide_slider_box_css(slider_uuid: str) -> str:
    """A style rule that hides the number box viser draws beside a slider (the element after
    the slider, which carries the slider's id), so that typing goes to the box applied on Enter."""
    return f'<style>[id="{slider_uuid}"] ~ * {{ display: none !important; }}</style>'


class EntryGate:
    """What the typed box holds, with no GUI: a value waits here until Enter applies it.

    Callbacks arrive on viser's thread pool and event loop, so every method takes the lock.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.held: float | None = None  # the box's latest typed value, waiting for Enter

    @property
    def typing(self) -> bool:
        return self.held is not None

    def typed(self, value: float) -> None:
        with self._lock:
            self.held = value

    def commit(self) -> float | None:
        """Enter, or the person moved on: the held value (None if nothing was typed)."""
        with self._lock:
            value, self.held = self.held, None
            return value

    def drop(self) -> bool:
        """The slider was dragged: a held value is dropped. Whether there was one."""
        with self._lock:
            had, self.held = self.held is not None, None
            return had


class LiveSlider:
    """A live parameter's slider, its typed box in a form, and a note while a value waits.

    `apply(value)` is called with each value to apply, already inside the slider's range.
    """

    def __init__(
        self, server: viser.ViserServer, spec: SliderRange, apply: Callable[[float], None]
    ) -> None:
        self.spec = spec
        self._apply = apply
        self.gate = EntryGate()
        gui = server.gui
        self._style = gui.add_html("")
        self.slider = gui.add_slider(
            slider_label(spec), min=spec.lo, max=spec.hi, step=spec.step, initial_value=spec.initial
        )
        self._style.content = hide_slider_box_css(self.slider._impl.uuid)  # viser: no public id
        with gui.add_form(None) as self.form:
            self.box = gui.add_number(
                box_label(spec),
                spec.initial,
                min=spec.lo,
                max=spec.hi,
                step=spec.step,
                hint=BOX_HINT,
            )
            self.note = gui.add_html("", visible=False)
        self.slider.on_update(self._on_drag)
        self.box.on_update(self._on_typed)
        self.form.on_submit(lambda _event: self.commit())
        # set by `watch_controls`: write a value into the box even where the server holds it
        # already (viser's setter then sends nothing, but the box may show a keystroke the
        # server never got)
        self.echo: Callable[[float], None] = self._set_box

    def _set_box(self, value: float) -> None:
        self.box.value = value  # type: ignore[misc]  # viser types the setter on a subclass

    def _on_drag(self, event: viser.GuiEvent) -> None:
        if event.client is None:
            return  # the loop set this slider itself: not a person's request
        value = self.spec.clamp(float(self.slider.value))
        if self.gate.drop():
            self._show_note(None)
        self._apply(value)
        self._set_box(value)

    def _on_typed(self, event: viser.GuiEvent) -> None:
        if event.client is None:
            return
        value = float(self.box.value)
        self.gate.typed(value)
        log.debug("%s: typed %r, held for Enter", self.spec.label, value)
        self._show_note(value)

    def commit(self) -> None:
        """Enter: apply what the box holds, clamped as the box clamps it; NaN (empty) is not."""
        value = self.gate.commit()
        self._show_note(None)
        if value is not None and math.isfinite(value):
            v = self.spec.clamp(value)
            self._apply(v)
            self.slider.value = v  # type: ignore[misc]  # viser types the setter on a subclass
        # the box shows what the walk runs: clamped, and where viser's throttle dropped the last
        # keystroke's value for the submit, the value the server had (never silently a
        # different number in the box than in the walk)
        self.echo(float(self.slider.value))

    def leave(self) -> None:
        """Another control was used: a typed value waiting here is applied."""
        if self.gate.typing:
            self.commit()

    def show(self, value: float) -> None:
        """The loop puts a value in force (a ramp's start, a loaded file): both controls show it."""
        self.slider.value = value  # type: ignore[misc]  # viser types the setter on a subclass
        self._set_box(value)

    @property
    def value(self) -> float:
        return float(self.slider.value)

    @property
    def disabled(self) -> bool:
        return bool(self.slider.disabled)

    @disabled.setter
    def disabled(self, disabled: bool) -> None:
        """A ramp drives this parameter: neither control takes a person's value meanwhile."""
        self.slider.disabled = disabled
        self.box.disabled = disabled

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


def watch_controls(server: viser.ViserServer, live: list[LiveSlider]) -> bool:
    """Route every control's update to the live parameters: any control other than a live
    parameter's own two applies the value typed into that parameter's box (the person left it).

    Returns False (and logs why) if this viser has no such message: a typed value then waits
    for Enter alone, and the viewer still works.
    """
    try:
        interface, (update,) = private_channel(server, "GuiUpdateMessage")
    except NoHook as exc:
        log.warning("a typed value waits for Enter alone: this viser has no hook (%s)", exc)
        return False
    owner = {}
    for s in live:  # viser 1.1: handles show no public id
        owner[s.slider._impl.uuid] = s
        owner[s.box._impl.uuid] = s

    def on_update(_client: Any, message: Any) -> None:
        mine = owner.get(message.uuid)
        for s in live:
            if s is not mine:
                s.leave()

    for s in live:
        s.echo = functools.partial(_echo, interface, update, s, s.box._impl.uuid)
    interface.register_handler(update, on_update)
    return True


def _echo(interface: Any, update: Any, live: LiveSlider, uuid: str, value: float) -> None:
    """Set the box and send its value to the browsers even if the server holds it already."""
    live.box.value = value  # type: ignore[misc]  # viser types the setter on a subclass
    interface.queue_message(update(uuid, {"value": value}))

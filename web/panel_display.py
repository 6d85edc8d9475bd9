"""The control panel's loop-thread side: what the loop shows in the panel and reads from it.

The loop never writes a value back into a control because a person changed it: the simulation
takes exactly what the box holds. The slider of a parameter a ramp drives is disabled while
the ramp runs and not written meanwhile; the loop writes it once when the ramp starts (its
start value) and once when it ends or is stopped (where it left the parameter), never within
`EDIT_QUIET_S` of a person's last change there. The readouts, the choices in force and the
diagrams are sent only when they changed.

A base class of `web.panels.Panels` (which builds the handles declared here), so that the
loop's methods sit apart from the GUI's construction and its callbacks
(web/panel_callbacks.py), whose threads never call them.
"""

from __future__ import annotations

import time

import viser

from web import controls
from web.entry import LiveSlider
from web.export import Settings
from web.panel_labels import PAUSE, PLAY, RAMP_START, RAMP_STOP
from web.readouts import Readouts, format_readouts, status_html

# The loop leaves a control alone this long after a person last changed it (typing pauses
# between keys are well under a second; the ramp is stopped by the first keystroke anyway).
EDIT_QUIET_S = 2.0


class PanelDisplay:
    """The loop thread's methods on the panel (the `show_*`/`sync_*` methods and `editing`)."""

    # the handles web/panels.py builds that the loop writes or reads
    live: dict[str, LiveSlider]
    play: viser.GuiButtonHandle
    step: viser.GuiButtonHandle
    ramp: viser.GuiButtonHandle
    speed: viser.GuiButtonGroupHandle
    camera: viser.GuiButtonGroupHandle
    ground: viser.GuiButtonGroupHandle
    ramp_param: viser.GuiButtonGroupHandle
    atlas_axis_buttons: viser.GuiButtonGroupHandle
    ramp_which: viser.GuiTextHandle
    ramp_start: viser.GuiNumberHandle[float]
    ramp_turn: viser.GuiNumberHandle[float]
    ramp_hold: viser.GuiNumberHandle[float]
    ramp_ramp: viser.GuiNumberHandle[float]
    job_duration: viser.GuiNumberHandle[float]
    d31_init: viser.GuiSliderHandle[float]
    api_url: viser.GuiTextHandle
    status: viser.GuiHtmlHandle
    readouts: dict[str, viser.GuiTextHandle]
    # what the loop last set or showed, and what the callbacks note for it
    ramp_param_name: str
    _edited_at: dict[str, float]
    _playing: bool
    _ramping: bool
    _disabled: str | None
    _last: dict[str, str]

    def editing(self, key: str, now: float | None = None) -> bool:
        """Whether a person changed control `key` within the last `EDIT_QUIET_S` seconds."""
        live = self.live.get(key)
        if live is not None and live.gate.typing:
            return True  # a typed value waits for Enter in this box
        t = self._edited_at.get(key)
        now = time.monotonic() if now is None else now
        return t is not None and now - t < EDIT_QUIET_S

    def sync_controls(
        self,
        playing: bool,
        ramping: str | None,
        write: dict[str, float] | None = None,
    ) -> None:
        """Reflect state the loop changed itself, without queueing requests.

        `ramping` is the parameter a running ramp drives (None: no ramp): its slider is
        disabled while the ramp runs, and nothing is written into it meanwhile. `write` holds
        values the loop sets into sliders once (a ramp's start, where a stopped ramp left its
        parameter); never while a person is editing that box, so a keystroke is never
        overwritten.
        """
        for key, value in (write or {}).items():
            live = self.live.get(key)
            if live is not None and abs(live.value - value) > 1e-9 and not self.editing(key):
                live.show(value)
        if ramping != self._disabled:
            if self._disabled is not None:
                self.live[self._disabled].disabled = False
            if ramping is not None:
                self.live[ramping].disabled = True
            self._disabled = ramping
        if playing != self._playing:
            self._playing = playing
            self.play.label = PAUSE if playing else PLAY
            self.step.disabled = playing
        is_ramping = ramping is not None
        if is_ramping != self._ramping:
            self._ramping = is_ramping
            self.ramp.label = RAMP_STOP if is_ramping else RAMP_START

    def show_d31_init(self, value: float) -> None:
        """Loop thread: a restart's initial Delta31 into its slider ("Start as tripod" puts
        pi there), so that "Reset with this initial Δ31" then restarts from the same value."""
        shown = round(value, 2)
        if abs(float(self.d31_init.value) - shown) > 1e-9:
            self.d31_init.value = shown  # type: ignore[misc]  # viser types the setter on a subclass

    def load_inputs(self, s: Settings) -> None:
        """Loop thread: the loaded file's ramp and job inputs into their boxes."""
        if s.ramp is not None:
            self.ramp_param_name = s.ramp.param
            self.ramp_which.value = controls.RAMP_LABELS[s.ramp.param]  # type: ignore[misc]  # viser types the setter on a subclass
            r = s.ramp
            boxes = ((self.ramp_start, r.start), (self.ramp_turn, r.turn),
                     (self.ramp_hold, r.hold_s), (self.ramp_ramp, r.ramp_s))  # fmt: skip
            for box, v in boxes:
                box.value = v  # type: ignore[misc]  # viser types the setter on a subclass
        self.job_duration.value = s.job_duration_s  # type: ignore[misc]  # viser types the setter on a subclass
        self.api_url.value = s.api_url  # type: ignore[misc]  # viser types the setter on a subclass
        label = controls.speed_label(s.speed)
        if label is not None:
            self.speed.value = label  # type: ignore[misc]  # viser types the setter on a subclass

    def show_choices(self, choices: dict[str, str]) -> None:
        """Each button group's label names the choice in force ("speed — 1x"): viser's button
        groups do not show which button was pressed last. Loop thread; sent only on change."""
        groups = {
            "speed": self.speed,
            "camera": self.camera,
            "ground": self.ground,
            "ramp drives": self.ramp_param,
            "atlas over": self.atlas_axis_buttons,
        }
        for name, choice in choices.items():
            label = f"{name} — {choice}"
            if self._last.get(f"choice:{name}") != label:
                self._last[f"choice:{name}"] = label
                groups[name].label = label

    def show_readouts(self, r: Readouts) -> None:
        for label, text in format_readouts(r).items():
            if self._last.get(label) != text:
                self._last[label] = text
                if label == "status":
                    self.status.content = status_html(text)
                else:
                    self.readouts[label].value = text  # type: ignore[misc]  # viser types the setter on a subclass

    def shown(self, label: str) -> str:
        """The text a readout shows now (for the benchmark; a str is replaced atomically)."""
        return self._last.get(label, "")

    def show_html(self, handle: viser.GuiHtmlHandle, content: str) -> None:
        if handle.content != content:
            handle.content = content

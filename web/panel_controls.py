"""The panel's "Controls" folder, a part of web/panels.py: the live parameters, speed, pause and
single step, the starts and reset, the windows, the 3D view's switches and the ground.

Its callbacks run on viser's thread pool and do one thing: put a request on the queue (and
note when a person last touched that control). When the loop thread sets a control itself (a
ramp's start value into its slider, the play button's label), viser calls the same callbacks
synchronously with `event.client is None`; those echoes are ignored, so the loop never queues
requests to itself (`queued`).

The loop never writes a value back into a control because a person changed it: the simulation
takes exactly what the box holds. The slider of a parameter a ramp drives is disabled while
the ramp runs and not written meanwhile; the loop writes it once when the ramp starts (its
start value) and once when it ends or is stopped (where it left the parameter), never within
`EDIT_QUIET_S` of a person's last change there (`sync`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import viser

from sim_core.contract import GROUND_HELP, METACHRONAL, TRIPOD, RampParam
from web import controls
from web.entry import LiveSlider
from web.panel_labels import (
    D31_WINDOW_LABEL,
    DRAW_3D,
    DRAW_3D_HINT,
    PAUSE,
    PLAY,
    PRESET_METACHRONAL,
    PRESET_TRIPOD,
    STEP,
    view_cost_html,
)
from web.readouts import note_html
from web.requests import (
    Request,
    RequestQueue,
    Reset,
    SetD31Window,
    SetDraw3D,
    SetFollow,
    SetFootfallWindow,
    SetGround,
    SetParam,
    SetPlaying,
    SetSpeed,
    StepCycle,
)

# The loop leaves a control alone this long after a person last changed it (typing pauses
# between keys are well under a second; the ramp is stopped by the first keystroke anyway).
EDIT_QUIET_S = 2.0


def queued(requests: RequestQueue, make: Callable[[], Request]) -> Callable[[viser.GuiEvent], None]:
    """A control's callback that queues `make()` when a person used it (not the loop's echo)."""

    def callback(event: viser.GuiEvent) -> None:
        if event.client is not None:
            requests.put(make())

    return callback


class WalkControls:
    """The "Controls" folder's controls, built in the folder open when it is made."""

    def __init__(
        self, server: viser.ViserServer, requests: RequestQueue, software_fps: float
    ) -> None:
        self._requests = requests
        # control key -> time.monotonic() of a person's last change (written by callbacks,
        # read by the loop; a float store is atomic)
        self._edited_at: dict[str, float] = {}
        self._playing = True  # what the play button says (the loop writes it, a click reads it)
        self._disabled: str | None = None  # the slider a running ramp has disabled
        self._gui = gui = server.gui
        # a drag streams, a typed number waits for Enter (web/entry.py)
        self.live: dict[str, LiveSlider] = {
            p.name: LiveSlider(server, p.slider, self._live(p.name)) for p in controls.LIVE
        }
        # Buttons, not a dropdown: a dropdown opens when Tab reaches it, and Tab out of the
        # slope box then spread the speed list over the plots. The status readout says the
        # speed in force.
        self.speed = gui.add_button_group("speed", tuple(controls.SPEEDS))
        self.speed.on_click(self._queue(lambda: SetSpeed(controls.speed_value(self.speed.value))))
        self.play = gui.add_button(PAUSE)
        self.play.on_click(self._queue(lambda: SetPlaying(not self._playing)))
        # while paused: one gait cycle, then paused again (the loop ignores it while playing)
        self.step = gui.add_button(STEP, disabled=True)
        self.step.on_click(self._queue(StepCycle))
        self.tripod = gui.add_button(PRESET_TRIPOD)
        self.tripod.on_click(self._queue(lambda: Reset(TRIPOD)))
        self.metachronal = gui.add_button(PRESET_METACHRONAL)
        self.metachronal.on_click(self._queue(lambda: Reset(METACHRONAL)))
        self.window = self._slider("footfall", controls.FOOTFALL_WINDOW_S, SetFootfallWindow)
        self.d31_window = gui.add_number(D31_WINDOW_LABEL, 0.0, min=0.0, max=3600.0, step=1.0)
        self.d31_window.on_update(self._on_d31_window)
        self.draw_3d = gui.add_checkbox(DRAW_3D, True, hint=DRAW_3D_HINT)
        self.draw_3d.on_update(self._queue(lambda: SetDraw3D(bool(self.draw_3d.value))))
        self.low_res = gui.add_html(view_cost_html(software_fps))
        self.camera = gui.add_button_group("camera", controls.CAMERA_MODES)  # as speed
        self.camera.on_click(self._queue(lambda: SetFollow(str(self.camera.value))))
        # the grounds by the core's names (controls.GROUNDS); what each is, under them
        self.ground = gui.add_button_group("ground", tuple(controls.GROUNDS), hint=GROUND_HELP)
        self.ground.on_click(
            self._queue(lambda: SetGround(controls.GROUNDS[str(self.ground.value)]))
        )
        self.ground_words = gui.add_html(note_html(GROUND_HELP))
        self.d31_init = self._slider("d31_init", controls.D31_INIT, None)
        self.reset = gui.add_button("Reset with this initial Δ31")
        self.reset.on_click(
            self._queue(lambda: Reset(controls.d31_init_value(self.d31_init.value)))
        )

    # --- viser's threads: callbacks that queue requests -----------------------------------------
    def _queue(self, make: Callable[[], Request]) -> Callable[[viser.GuiEvent], None]:
        return queued(self._requests, make)

    def _live(self, name: RampParam) -> Callable[[float], None]:
        """What a live slider does with a value to apply: note the edit, queue the request."""

        def apply(value: float) -> None:
            self._edited_at[name] = time.monotonic()
            self._requests.put(SetParam(name, value))

        return apply

    def _slider(
        self, key: str, spec: controls.SliderRange, make: Callable[[float], Request] | None
    ) -> viser.GuiSliderHandle[float]:
        label = f"{spec.label} ({spec.unit})" if spec.unit else spec.label
        handle = self._gui.add_slider(
            label, min=spec.lo, max=spec.hi, step=spec.step, initial_value=spec.initial
        )
        if make is None:
            return handle

        def callback(event: viser.GuiEvent) -> None:
            if event.client is None:
                return  # the loop set this control itself: not a user's request
            self._edited_at[key] = time.monotonic()
            value = spec.typed(handle.value)
            if value is not None:
                self._requests.put(make(value))

        handle.on_update(callback)
        return handle

    def _on_d31_window(self, event: viser.GuiEvent) -> None:
        if event.client is None:
            return
        try:
            w = float(self.d31_window.value)
        except (TypeError, ValueError):
            return
        if math.isfinite(w) and w >= 0:
            self._requests.put(SetD31Window(None if w == 0 else w))

    # --- the loop thread ------------------------------------------------------------------------
    def editing(self, key: str, now: float | None = None) -> bool:
        """Whether a person changed control `key` within the last `EDIT_QUIET_S` seconds."""
        live = self.live.get(key)
        if live is not None and live.gate.typing:
            return True  # a typed value waits for Enter in this box
        t = self._edited_at.get(key)
        now = time.monotonic() if now is None else now
        return t is not None and now - t < EDIT_QUIET_S

    def sync(self, playing: bool, ramping: str | None, write: dict[str, float]) -> None:
        """Reflect state the loop changed itself, without queueing requests.

        `ramping` is the parameter a running ramp drives (None: no ramp): its slider is
        disabled while the ramp runs, and nothing is written into it meanwhile. `write` holds
        values the loop sets into sliders once (a ramp's start, where a stopped ramp left its
        parameter); never while a person is editing that box, so a keystroke is never
        overwritten.
        """
        for key, value in write.items():
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

    def show_d31_init(self, value: float) -> None:
        """A restart's initial Delta31 into its slider ("Start as tripod" puts pi there), so
        that "Reset with this initial Δ31" then restarts from the same value."""
        shown = round(value, 2)
        if abs(float(self.d31_init.value) - shown) > 1e-9:
            self.d31_init.value = shown  # type: ignore[misc]  # viser types the setter on a subclass

    def show_speed(self, speed: float | None) -> None:
        """A loaded file's speed on its button group (the status line says it too)."""
        label = controls.speed_label(speed)
        if label is not None:
            self.speed.value = label  # type: ignore[misc]  # viser types the setter on a subclass

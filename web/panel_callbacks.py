"""The control panel's callbacks: sliders and buttons that only queue requests.

Every callback here runs on viser's thread pool and does one thing: put a request on the queue
(and note when a person last touched that control). When the loop thread sets a control itself
(a ramp's start value into its slider, the play button's label), viser calls the same callbacks
synchronously with `event.client is None`; those echoes are ignored, so the loop never queues
requests to itself.

A base class of `web.panels.Panels` (which builds the handles and wires these callbacks to
them), so that what runs on viser's threads sits apart from the GUI's construction and from
the loop's side of the panel (web/panel_display.py).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import viser

from sim_core.contract import Ramp
from web import controls
from web.panel_display import PanelDisplay
from web.readouts import note_html
from web.requests import (
    Export,
    LoadSettings,
    Request,
    RequestQueue,
    SetD31Window,
    SetParam,
    SetPlaying,
    StartRamp,
    StopRamp,
)
from web.settings_file import load_settings


class PanelCallbacks(PanelDisplay):
    """The callbacks `Panels` wires to its controls (and `ramp_settings`, which reads them)."""

    server: viser.ViserServer
    requests: RequestQueue
    d31_window: viser.GuiNumberHandle[float]
    load: viser.GuiUploadButtonHandle
    load_note: viser.GuiHtmlHandle
    atlas_axis: str

    def _slider(
        self,
        key: str,
        spec: controls.SliderRange,
        make: Callable[[float], Request] | None,
    ) -> viser.GuiSliderHandle:
        label = f"{spec.label} ({spec.unit})" if spec.unit else spec.label
        handle = self.server.gui.add_slider(
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
                self.requests.put(make(value))

        handle.on_update(callback)
        return handle

    def _live(self, key: str) -> Callable[[float], None]:
        """What a live slider does with a value to apply: note the edit, queue the request."""

        def apply(value: float) -> None:
            self._edited_at[key] = time.monotonic()
            self.requests.put(SetParam(key, value))

        return apply

    def _queue(self, make: Callable[[], Request]) -> Callable[[viser.GuiEvent], None]:
        def callback(event: viser.GuiEvent) -> None:
            if event.client is None:
                return  # the loop set this control itself: not a user's request
            self.requests.put(make())

        return callback

    def _on_play(self, event: viser.GuiEvent) -> None:
        if event.client is not None:
            self.requests.put(SetPlaying(not self._playing))

    def _on_ramp(self, event: viser.GuiEvent) -> None:
        if event.client is None:
            return
        if self._ramping:
            self.requests.put(StopRamp())
            return
        try:
            ramp = self.ramp_settings()
        except (TypeError, ValueError):
            return  # a box holds no number yet
        self.requests.put(StartRamp(ramp))

    def ramp_settings(self) -> Ramp:
        """The ramp the inputs describe (each value clamped to its control's range)."""
        return controls.make_ramp(
            self.ramp_param_name,
            float(self.ramp_start.value),
            float(self.ramp_turn.value),
            float(self.ramp_hold.value),
            float(self.ramp_ramp.value),
        )

    def _on_ramp_param(self, event: viser.GuiEvent) -> None:
        """A new parameter: its range and the default sweep into the start and turn boxes."""
        if event.client is None:
            return
        param = controls.RAMP_BUTTONS.get(str(self.ramp_param.value))
        if param is None or self._ramping:
            return  # a running ramp keeps its parameter
        self.ramp_param_name = param
        self.ramp_which.value = controls.RAMP_LABELS[param]  # type: ignore[misc]  # viser types the setter on a subclass
        rng = controls.RAMP_SLIDERS[param]
        start, turn = controls.RAMP_DEFAULTS[param]
        for box, value in ((self.ramp_start, start), (self.ramp_turn, turn)):
            box.step = rng.step
            box.min = rng.lo
            box.max = rng.hi
            box.value = value  # type: ignore[misc]  # viser types the setter on a subclass

    def _on_d31_window(self, event: viser.GuiEvent) -> None:
        if event.client is None:
            return
        try:
            w = float(self.d31_window.value)
        except (TypeError, ValueError):
            return
        if math.isfinite(w) and w >= 0:
            self.requests.put(SetD31Window(None if w == 0 else w))

    def _on_atlas_axis(self, event: viser.GuiEvent) -> None:
        if event.client is not None:
            self.atlas_axis = str(self.atlas_axis_buttons.value)

    def _on_load(self, event: viser.GuiEvent) -> None:
        """A settings file arrived: read it here (pure), the loop applies it."""
        if event.client is None:
            return
        upload = self.load.value
        try:
            settings = load_settings(upload.content)
        except ValueError as exc:
            self.load_note.content = note_html(f"{upload.name} not loaded: {exc}", error=True)
            return
        self.load_note.content = note_html(f"loaded {upload.name}")
        self.requests.put(LoadSettings(settings))

    def _export(self, what: str) -> Callable[[viser.GuiEvent], None]:
        def callback(event: viser.GuiEvent) -> None:
            client = event.client
            if client is None:
                return

            def send(name: str, data: bytes) -> None:
                client.send_file_download(name, data, save_immediately=True)

            self.requests.put(Export(what, send))

        return callback

"""Parts of the control panel (web/panels.py composes them): the ramp's inputs, the export
buttons with the settings file's upload, and the readout lines.

Each part builds its controls in the folder open when it is made, wires their callbacks (which
run on viser's thread pool and only queue requests or read a file) and holds what the loop
thread shows in them; a callback ignores the loop's own writes (`event.client is None`).
"""

from __future__ import annotations

from collections.abc import Callable

import viser

from sim_core.contract import Ramp, RampParam
from web import controls
from web.panel_labels import EXPORT_BUTTONS, LOAD_SETTINGS, RAMP_START, RAMP_STOP
from web.readouts import Readouts, format_readouts, note_html, status_html
from web.requests import Export, LoadSettings, RequestQueue, StartRamp, StopRamp
from web.settings_file import load_settings


class RampInputs:
    """Which parameter the ramp drives, its start and turn, its hold and ramp times, and the
    button that starts or stops it."""

    def __init__(self, server: viser.ViserServer, requests: RequestQueue) -> None:
        self._requests = requests
        gui = server.gui
        # buttons, not a dropdown (as speed): which parameter the ramp drives
        self.param = gui.add_button_group("ramp drives", tuple(controls.RAMP_BUTTONS))
        self.param_name: RampParam = "beta"  # written by the callback, read by the loop
        self.param.on_click(self._on_param)
        self.which = gui.add_text("ramped", controls.RAMP_LABELS["beta"], disabled=True)
        start, turn = controls.RAMP_DEFAULTS["beta"]
        self.start = gui.add_number("ramp start", start, step=0.005)
        self.turn = gui.add_number("ramp turn", turn, step=0.005)
        h, r = controls.RAMP_HOLD_S, controls.RAMP_RAMP_S
        self.hold_s = gui.add_number("hold (s)", h.initial, min=h.lo, max=h.hi, step=h.step)
        self.ramp_s = gui.add_number("ramp (s)", r.initial, min=r.lo, max=r.hi, step=r.step)
        self.button = gui.add_button(RAMP_START)
        self.button.on_click(self._on_button)
        self._ramping = False  # what the button says (the loop writes it, a click reads it)

    def settings(self) -> Ramp:
        """The ramp the inputs describe (each value clamped to its control's range)."""
        return controls.make_ramp(
            self.param_name,
            float(self.start.value),
            float(self.turn.value),
            float(self.hold_s.value),
            float(self.ramp_s.value),
        )

    def _on_button(self, event: viser.GuiEvent) -> None:
        if event.client is None:
            return
        if self._ramping:
            self._requests.put(StopRamp())
            return
        try:
            ramp = self.settings()
        except (TypeError, ValueError):
            return  # a box holds no number yet
        self._requests.put(StartRamp(ramp))

    def _on_param(self, event: viser.GuiEvent) -> None:
        """A new parameter: its range and the default sweep into the start and turn boxes."""
        if event.client is None:
            return
        param = controls.RAMP_BUTTONS.get(str(self.param.value))
        if param is None or self._ramping:
            return  # a running ramp keeps its parameter
        self.param_name = param
        self.which.value = controls.RAMP_LABELS[param]  # type: ignore[misc]  # viser types the setter on a subclass
        rng = controls.RAMP_SLIDERS[param]
        start, turn = controls.RAMP_DEFAULTS[param]
        for box, value in ((self.start, start), (self.turn, turn)):
            box.step = rng.step
            box.min = rng.lo
            box.max = rng.hi
            box.value = value  # type: ignore[misc]  # viser types the setter on a subclass

    def sync(self, ramping: bool) -> None:
        """Loop thread: the button says what a click does now."""
        if ramping != self._ramping:
            self._ramping = ramping
            self.button.label = RAMP_STOP if ramping else RAMP_START

    def load(self, ramp: Ramp) -> None:
        """Loop thread: a loaded file's ramp into the inputs (set up, not started)."""
        self.param_name = ramp.param
        self.which.value = controls.RAMP_LABELS[ramp.param]  # type: ignore[misc]  # viser types the setter on a subclass
        boxes = ((self.start, ramp.start), (self.turn, ramp.turn),
                 (self.hold_s, ramp.hold_s), (self.ramp_s, ramp.ramp_s))  # fmt: skip
        for box, v in boxes:
            box.value = v  # type: ignore[misc]  # viser types the setter on a subclass


class ExportButtons:
    """A download button per export (web/export.py), and the settings file read back."""

    def __init__(self, server: viser.ViserServer, requests: RequestQueue) -> None:
        self._requests = requests
        gui = server.gui
        self.buttons = {}
        for label, what in EXPORT_BUTTONS.items():
            button = gui.add_button(label)
            button.on_click(self._export(what))
            self.buttons[what] = button
        # the settings file read back: the walk restarts at what it says
        self.load = gui.add_upload_button(LOAD_SETTINGS, mime_type="application/json")
        self.load.on_upload(self._on_load)
        self.note = gui.add_html("")

    def _export(self, what: str) -> Callable[[viser.GuiEvent], None]:
        def callback(event: viser.GuiEvent) -> None:
            client = event.client
            if client is None:
                return

            def send(name: str, data: bytes) -> None:
                client.send_file_download(name, data, save_immediately=True)

            self._requests.put(Export(what, send))

        return callback

    def _on_load(self, event: viser.GuiEvent) -> None:
        """A settings file arrived: read it here (pure), the loop applies it."""
        if event.client is None:
            return
        upload = self.load.value
        try:
            settings = load_settings(upload.content)
        except ValueError as exc:
            self.note.content = note_html(f"{upload.name} not loaded: {exc}", error=True)
            return
        self.note.content = note_html(f"loaded {upload.name}")
        self._requests.put(LoadSettings(settings))


class ReadoutLines:
    """The status line and a line per readout; each sent only when its text changed."""

    def __init__(self, gui: viser.GuiApi) -> None:
        blank = format_readouts(
            Readouts(controls.BETA.initial, 0.0, None, None, "–", 0.0, None, None, 1.0, None, "")
        )
        self.status = gui.add_html(status_html(blank.pop("status")))
        self.lines = {k: gui.add_text(k, v, disabled=True) for k, v in blank.items()}
        self._last: dict[str, str] = {}

    def show(self, r: Readouts) -> None:
        """Loop thread."""
        for label, text in format_readouts(r).items():
            if self._last.get(label) != text:
                self._last[label] = text
                if label == "status":
                    self.status.content = status_html(text)
                else:
                    self.lines[label].value = text  # type: ignore[misc]  # viser types the setter on a subclass

    def shown(self, label: str) -> str:
        """The text a readout shows now (for the benchmark; a str is replaced atomically)."""
        return self._last.get(label, "")

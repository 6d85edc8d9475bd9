"""The control panel: sliders and buttons that only queue requests, readouts and diagrams.

Every callback here runs on viser's thread pool and does one thing: put a request on the queue
(and note when a person last touched that control). When the loop thread sets a control itself
(a ramp's start value into its slider, the play button's label), viser calls the same callbacks
synchronously with `event.client is None`; those echoes are ignored, so the loop never queues
requests to itself.

Typed values. A number box sends every keystroke ("0.62" arrives as 0, 0, 0.6, 0.62), so:
- the live parameters (beta, mass, slope) each have a slider that streams and a number box under
  it that applies on Enter, or when the person uses another control, never per keystroke
  (`web.entry.LiveSlider`);
- in the other boxes a value that cannot be one yet (outside the range, or not a number) is not
  applied (`SliderRange.typed`); the box clamps it itself when the person leaves it;
- the loop never writes a value back into a control because a person changed it: the simulation
  takes exactly what the box holds. The slider of a parameter a ramp drives is disabled while
  the ramp runs and not written meanwhile; the loop writes it once when the ramp starts (its
  start value) and once when it ends or is stopped (where it left the parameter), never within
  `EDIT_QUIET_S` of a person's last change there.

All browsers see the same panel (`server.gui` state is shared), which is why there is one
simulation for everyone (docs/VIEWER.md).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import viser

from sim_core.contract import METACHRONAL, TRIPOD, Ramp
from web import controls
from web.caption import CAPTION
from web.entry import LiveSlider, watch_controls
from web.export import Settings, load_settings
from web.jobs import JobView, job_status_html
from web.paths import DEFAULT_API_URL
from web.readouts import Readouts, format_readouts, note_html, status_html
from web.requests import (
    Export,
    LoadSettings,
    OpenJob,
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
    StartRamp,
    StepCycle,
    StopRamp,
    SubmitJob,
)

PLAY, PAUSE = "Play", "Pause"
STEP = "Step one cycle"
SUBMIT_RUN, SUBMIT_RAMP = "Submit as a run job", "Submit the ramp as a hysteresis job"
OPEN_JOB = "Open job by id"
LOAD_SETTINGS = "Load settings (JSON)"
DRAW_3D = "draw the 3D walk"
DRAW_3D_HINT = (
    "Off: the 3D view holds its last pose and the simulation gets the core a browser without a "
    "GPU spends drawing it; the plots and readouts stay live."
)
# viser reads a fixed device-pixel ratio from the page's URL (its `fixedDpr` dev setting): at
# half resolution a browser drawing WebGL in software leaves its page's main thread free (1-7%
# in long tasks against 93-97% at full, measured by benchmarks/viewer_rtf.py --query), so the
# readouts refresh at 4.6 Hz instead of 3.0-3.5 Hz at 1x. A link, not a default: on a GPU the
# full resolution costs nothing.
LOW_RES_HTML = (
    '<div style="font-size:0.75em;padding-left:0.5em">No GPU (software WebGL)? '
    '<a href="?fixedDpr=0.5">the 3D view at half resolution</a> · <a href="?">full</a></div>'
)
RAMP_START, RAMP_STOP = "Start ramp", "Stop ramp"
# export buttons: label -> what (web/export.py)
EXPORT_BUTTONS = {
    "Δ31 trace (CSV)": "d31",
    "footfall (CSV)": "footfall",
    "ramp path (CSV)": "ramp",
    "settings (JSON)": "settings",
}
# the ramp's parameter buttons: label -> RunSpec field
D31_WINDOW_LABEL = "Δ31 window (s, 0 = whole run)"
PRESET_TRIPOD, PRESET_METACHRONAL = "Start as tripod (Δ31 = π)", "Start as metachronal (2π/3)"
# The loop leaves a control alone this long after a person last changed it (typing pauses
# between keys are well under a second; the ramp is stopped by the first keystroke anyway).
EDIT_QUIET_S = 2.0


class Panels:
    """Builds the GUI once; the loop thread calls the `show_*`/`sync_*` methods."""

    def __init__(self, server: viser.ViserServer, requests: RequestQueue) -> None:
        self.server = server
        self.requests = requests
        # control key -> time.monotonic() of a person's last change (written by callbacks,
        # read by the loop; a float store is atomic)
        self._edited_at: dict[str, float] = {}
        gui = server.gui
        gui.configure_theme(control_width="large", dark_mode=False)
        # Plots first: at 1280x800 the footfall diagram and Delta31 show without scrolling.
        gui.add_markdown(CAPTION)
        with gui.add_folder("Gait"):
            self.footfall = gui.add_html("<em>footfall: waiting for the first steps</em>")
            self.d31 = gui.add_html("<em>Δ31: waiting for leg-1 touchdowns</em>")
            self.return_map = gui.add_html("<em>return map: waiting for touchdowns</em>")
        with gui.add_folder("Controls"):
            # a drag streams, a typed number waits for Enter (web/entry.py)
            self.live = {
                p.name: LiveSlider(server, p.slider, self._live(p.name)) for p in controls.LIVE
            }
            # Buttons, not a dropdown: a dropdown opens when Tab reaches it, and Tab out of the
            # slope box then spread the speed list over the plots. The status readout says
            # the speed in force.
            self.speed = gui.add_button_group("speed", tuple(controls.SPEEDS))
            self.speed.on_click(
                self._queue(lambda: SetSpeed(controls.speed_value(self.speed.value)))
            )
            self.play = gui.add_button(PAUSE)
            self.play.on_click(self._on_play)
            self._playing = True
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
            self.low_res = gui.add_html(LOW_RES_HTML)
            self.camera = gui.add_button_group("camera", controls.CAMERA_MODES)  # as speed
            self.camera.on_click(self._queue(lambda: SetFollow(str(self.camera.value))))
            # the paper's ground keeps walking up and down a slope; today's contact turns
            self.ground = gui.add_button_group("ground", tuple(controls.GROUNDS))
            self.ground.on_click(
                self._queue(lambda: SetGround(controls.GROUNDS[str(self.ground.value)]))
            )
            self.d31_init = self._slider("d31_init", controls.D31_INIT, None)
            self.reset = gui.add_button("Reset with this initial Δ31")
            self.reset.on_click(
                self._queue(lambda: Reset(controls.d31_init_value(self.d31_init.value)))
            )
        with gui.add_folder("Ramp (hold, ramp, back, hold)"):
            # buttons, not a dropdown (as speed): which parameter the ramp drives
            self.ramp_param = gui.add_button_group("ramp drives", tuple(controls.RAMP_BUTTONS))
            self.ramp_param_name = "beta"  # written by the callback, read by the loop
            self.ramp_param.on_click(self._on_ramp_param)
            self.ramp_which = gui.add_text("ramped", controls.RAMP_LABELS["beta"], disabled=True)
            start, turn = controls.RAMP_DEFAULTS["beta"]
            self.ramp_start = gui.add_number("ramp start", start, step=0.005)
            self.ramp_turn = gui.add_number("ramp turn", turn, step=0.005)
            h, r = controls.RAMP_HOLD_S, controls.RAMP_RAMP_S
            self.ramp_hold = gui.add_number("hold (s)", h.initial, min=h.lo, max=h.hi, step=h.step)
            self.ramp_ramp = gui.add_number("ramp (s)", r.initial, min=r.lo, max=r.hi, step=r.step)
            self.ramp = gui.add_button(RAMP_START)
            self.ramp.on_click(self._on_ramp)
            self.ramp_plot = gui.add_html("<em>a ramp's path: Δ31 against what it ramps</em>")
            self._ramping = False
            self._disabled: str | None = None  # the slider a running ramp has disabled
        with gui.add_folder("Bifurcation"):
            self.bifurcation = gui.add_html("<em>bifurcation diagram</em>")
        with gui.add_folder("Drift surface"):
            self.surface = gui.add_html("<em>drift surface</em>")
        with gui.add_folder("Atlas"):
            self.atlas_axis_buttons = gui.add_button_group("atlas over", ("mass", "slope"))
            self.atlas_axis = "mass"  # read by the loop; a str store is atomic
            self.atlas_axis_buttons.on_click(self._on_atlas_axis)
            self.atlas = gui.add_html("<em>gait atlas</em>")
        with gui.add_folder("Export"):
            self.exports = {}
            for label, what in EXPORT_BUTTONS.items():
                button = gui.add_button(label)
                button.on_click(self._export(what))
                self.exports[what] = button
            # the settings file read back: the walk restarts at what it says
            self.load = gui.add_upload_button(LOAD_SETTINGS, mime_type="application/json")
            self.load.on_upload(self._on_load)
            self.load_note = gui.add_html("")
        with gui.add_folder("Submit as a job"):
            self.api_url = gui.add_text("API URL", DEFAULT_API_URL)
            self.job_duration = gui.add_number("job duration (s)", 30.0, min=1.0, max=600.0)
            self.submit_run = gui.add_button(SUBMIT_RUN)
            self.submit_run.on_click(self._queue(lambda: SubmitJob("run")))
            self.submit_ramp = gui.add_button(SUBMIT_RAMP)
            self.submit_ramp.on_click(self._queue(lambda: SubmitJob("hysteresis")))
            self.job_id = gui.add_text("job id", "")
            self.open_job = gui.add_button(OPEN_JOB)
            self.open_job.on_click(self._queue(lambda: OpenJob(str(self.job_id.value))))
            self.job_status = gui.add_html(job_status_html(JobView()))
            self.job = gui.add_html("<em>the current settings as a REST job</em>")
        with gui.add_folder("Readouts"):
            blank = format_readouts(
                Readouts(
                    controls.BETA.initial, 0.0, None, None, "–", 0.0, None, None, 1.0, None, ""
                )
            )
            self.status = gui.add_html(status_html(blank.pop("status")))
            self.readouts = {k: gui.add_text(k, v, disabled=True) for k, v in blank.items()}
        self._last: dict[str, str] = {}
        self.typed_leaves = watch_controls(server, list(self.live.values()))

    # --- callbacks: queue only -----------------------------------------------------------------
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

    def _export(self, what: str) -> Callable[[viser.GuiEvent], None]:
        def callback(event: viser.GuiEvent) -> None:
            client = event.client
            if client is None:
                return

            def send(name: str, data: bytes) -> None:
                client.send_file_download(name, data, save_immediately=True)

            self.requests.put(Export(what, send))

        return callback

    # --- loop thread only ----------------------------------------------------------------------
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

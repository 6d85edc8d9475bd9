"""The control panel: sliders and buttons that only queue requests, readouts and diagrams.

`Panels` builds the GUI once and wires each control to its callback. The callbacks run on
viser's thread pool and only queue requests, ignoring the echoes of the loop's own writes
(web/panel_callbacks.py); the loop thread alone calls the `show_*`/`sync_*` methods
(web/panel_display.py); the labels, which tests and the benchmark look controls up by, are
web/panel_labels.py's.

Typed values. A number box sends every keystroke ("0.62" arrives as 0, 0, 0.6, 0.62), so:
- the live parameters (beta, mass, slope) each have a slider that streams and a number box under
  it that applies on Enter, or when the person uses another control, never per keystroke
  (`web.entry.LiveSlider`);
- in the other boxes a value that cannot be one yet (outside the range, or not a number) is not
  applied (`SliderRange.typed`); the box clamps it itself when the person leaves it;
- the loop never writes a value back into a control because a person changed it: the simulation
  takes exactly what the box holds (web/panel_display.py: a ramp's slider, `EDIT_QUIET_S`).

All browsers see the same panel (`server.gui` state is shared), which is why there is one
simulation for everyone (docs/VIEWER.md).
"""

from __future__ import annotations

import viser

from sim_core.contract import GROUND_HELP, METACHRONAL, TRIPOD
from web import controls
from web.caption import CAPTION
from web.entry import LiveSlider, watch_controls
from web.job_panel import JobRows
from web.jobs import JobView, job_status_html
from web.panel_callbacks import PanelCallbacks
from web.panel_labels import (
    COMPUTE_SURFACE,
    D31_WINDOW_LABEL,
    DRAW_3D,
    DRAW_3D_HINT,
    EXPORT_BUTTONS,
    LOAD_SETTINGS,
    OPEN_JOB,
    PAUSE,
    PRESET_METACHRONAL,
    PRESET_TRIPOD,
    RAMP_PLOT_EMPTY,
    RAMP_START,
    STEP,
    SUBMIT_RAMP,
    SUBMIT_RUN,
    view_cost_html,
)
from web.paths import DEFAULT_API_URL
from web.readouts import Readouts, format_readouts, note_html, status_html
from web.requests import (
    OpenJob,
    RequestQueue,
    Reset,
    SetDraw3D,
    SetFollow,
    SetFootfallWindow,
    SetGround,
    SetSpeed,
    StepCycle,
    SubmitJob,
    SubmitSurface,
)
from web.return_map_plot import add_return_map


class Panels(PanelCallbacks):
    """Builds the GUI once; the loop thread calls the `show_*`/`sync_*` methods."""

    def __init__(
        self, server: viser.ViserServer, requests: RequestQueue, software_fps: float
    ) -> None:
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
            self.return_map = add_return_map(gui)  # uPlot: the one chart that fits it
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
            self.ramp_plot = gui.add_html(RAMP_PLOT_EMPTY)
            self._ramping = False
            self._disabled: str | None = None  # the slider a running ramp has disabled
        with gui.add_folder("Bifurcation"):
            self.bifurcation = gui.add_html("<em>bifurcation diagram</em>")
        with gui.add_folder("Drift surface"):
            self.surface = gui.add_html("<em>drift surface</em>")
            # shown only while no surface of the walk's conditions exists (web/surfaces.py)
            self.surface_compute = gui.add_button(COMPUTE_SURFACE, visible=False)
            self.surface_compute.on_click(self._queue(SubmitSurface))
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
            # every job this viewer submitted or opened: cancel, replay (web/job_panel.py)
            self.job_rows = JobRows(gui, gui.add_folder("Jobs from this viewer"), requests)
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

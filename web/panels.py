"""The control panel: built once from its parts, in the order a person reads it.

Parts (each builds its controls, wires their callbacks and keeps what the loop shows in them):
the "Controls" folder (web/panel_controls.py: live parameters, speed, pause, starts, windows,
ground), the ramp's inputs, the export buttons and the readout lines (web/panel_parts.py), the
job list (web/job_panel.py). The chart panels' handles are the panel's own: the painters
(web/painter.py) draw into them. Callbacks run on viser's thread pool and only queue requests,
ignoring the echoes of the loop's own writes; the loop thread alone calls the `show_*`/`sync`
/`load` methods; the labels, which tests and the benchmark look controls up by, are
web/panel_labels.py's.

Typed values. A number box sends every keystroke ("0.62" arrives as 0, 0, 0.6, 0.62), so:
- the live parameters (beta, mass, slope) each have a slider that streams and a number box under
  it that applies on Enter, or when the person uses another control, never per keystroke
  (`web.entry.LiveSlider`);
- in the other boxes a value that cannot be one yet (outside the range, or not a number) is not
  applied (`SliderRange.typed`); the box clamps it itself when the person leaves it;
- the loop never writes a value back into a control because a person changed it: the simulation
  takes exactly what the box holds (web/panel_controls.py: a ramp's slider, `EDIT_QUIET_S`).

All browsers see the same panel (`server.gui` state is shared), which is why there is one
simulation for everyone (docs/VIEWER.md).
"""

from __future__ import annotations

import viser

from sim_core.contract import Ramp
from web.caption import CAPTION
from web.entry import watch_controls
from web.job_panel import JobRows
from web.jobs import JobView, job_status_html
from web.panel_controls import WalkControls, queued
from web.panel_labels import COMPUTE_SURFACE, OPEN_JOB, RAMP_PLOT_EMPTY, SUBMIT_RAMP, SUBMIT_RUN
from web.panel_parts import ExportButtons, RampInputs, ReadoutLines
from web.paths import DEFAULT_API_URL
from web.requests import OpenJob, RequestQueue, SubmitJob, SubmitSurface
from web.return_map_plot import add_return_map
from web.settings_file import JobInputs, Settings


class Panels:
    """The GUI's parts and chart panels; the loop thread calls the `show_*`/`sync`/`load`
    methods."""

    def __init__(
        self, server: viser.ViserServer, requests: RequestQueue, software_fps: float
    ) -> None:
        gui = server.gui
        gui.configure_theme(control_width="large", dark_mode=False)
        # Plots first: at 1280x800 the footfall diagram and Delta31 show without scrolling.
        gui.add_markdown(CAPTION)
        with gui.add_folder("Gait"):
            self.footfall = gui.add_html("<em>footfall: waiting for the first steps</em>")
            self.d31 = gui.add_html("<em>Δ31: waiting for leg-1 touchdowns</em>")
            self.return_map = add_return_map(gui)  # uPlot: the one chart that fits it
        with gui.add_folder("Controls"):
            self.walk = WalkControls(server, requests, software_fps)
        with gui.add_folder("Ramp (hold, ramp, back, hold)"):
            self.ramp = RampInputs(server, requests)
            self.ramp_plot = gui.add_html(RAMP_PLOT_EMPTY)
        with gui.add_folder("Bifurcation"):
            self.bifurcation = gui.add_html("<em>bifurcation diagram</em>")
        with gui.add_folder("Drift surface"):
            self.surface = gui.add_html("<em>drift surface</em>")
            # shown only while no surface of the walk's conditions exists (web/surfaces.py)
            self.surface_compute = gui.add_button(COMPUTE_SURFACE, visible=False)
            self.surface_compute.on_click(queued(requests, SubmitSurface))
        with gui.add_folder("Atlas"):
            self.atlas_axis_buttons = gui.add_button_group("atlas over", ("mass", "slope"))
            self.atlas_axis = "mass"  # read by the loop; a str store is atomic
            self.atlas_axis_buttons.on_click(self._on_atlas_axis)
            self.atlas = gui.add_html("<em>gait atlas</em>")
        with gui.add_folder("Export"):
            self.exports = ExportButtons(server, requests)
        with gui.add_folder("Submit as a job"):
            self.api_url = gui.add_text("API URL", DEFAULT_API_URL)
            self.job_duration = gui.add_number("job duration (s)", 30.0, min=1.0, max=600.0)
            self.submit_run = gui.add_button(SUBMIT_RUN)
            self.submit_run.on_click(queued(requests, lambda: SubmitJob("run")))
            self.submit_ramp = gui.add_button(SUBMIT_RAMP)
            self.submit_ramp.on_click(queued(requests, lambda: SubmitJob("hysteresis")))
            self.job_id = gui.add_text("job id", "")
            self.open_job = gui.add_button(OPEN_JOB)
            self.open_job.on_click(queued(requests, lambda: OpenJob(str(self.job_id.value))))
            self.job_status = gui.add_html(job_status_html(JobView()))
            # every job this viewer submitted or opened: cancel, replay (web/job_panel.py)
            self.job_rows = JobRows(gui, gui.add_folder("Jobs from this viewer"), requests)
            self.job = gui.add_html("<em>the current settings as a REST job</em>")
        with gui.add_folder("Readouts"):
            self.readouts = ReadoutLines(gui)
        self._choices: dict[str, str] = {}  # each button group's label last sent
        self.typed_leaves = watch_controls(server, list(self.walk.live.values()))

    def _on_atlas_axis(self, event: viser.GuiEvent) -> None:
        if event.client is not None:
            self.atlas_axis = str(self.atlas_axis_buttons.value)

    # --- the loop thread ------------------------------------------------------------------------
    def sync(self, playing: bool, ramping: str | None, write: dict[str, float]) -> None:
        """State the loop changed itself into the controls (web/panel_controls.py's `sync`),
        without queueing requests; the ramp's button says whether one runs."""
        self.walk.sync(playing, ramping, write)
        self.ramp.sync(ramping is not None)

    def job_inputs(self) -> JobInputs:
        """What the ramp and job inputs hold (a box without a number: its default)."""
        ramp: Ramp | None
        try:
            ramp = self.ramp.settings()
        except (TypeError, ValueError):
            ramp = None
        try:
            duration = min(600.0, max(1.0, float(self.job_duration.value)))
        except (TypeError, ValueError):
            duration = 30.0
        api_url = str(self.api_url.value).strip() or DEFAULT_API_URL
        return JobInputs(ramp, duration, api_url)

    def load(self, s: Settings) -> None:
        """A loaded file's ramp, job inputs and speed into their controls (set up, not
        started; the walk itself restarts in the loop)."""
        if s.ramp is not None:
            self.ramp.load(s.ramp)
        self.job_duration.value = s.job_duration_s  # type: ignore[misc]  # viser types the setter on a subclass
        self.api_url.value = s.api_url  # type: ignore[misc]  # viser types the setter on a subclass
        self.walk.show_speed(s.speed)

    def show_choices(self, choices: dict[str, str]) -> None:
        """Each button group's label names the choice in force ("speed — 1x"): viser's button
        groups do not show which button was pressed last. Sent only on change."""
        groups = {
            "speed": self.walk.speed,
            "camera": self.walk.camera,
            "ground": self.walk.ground,
            "ramp drives": self.ramp.param,
            "atlas over": self.atlas_axis_buttons,
        }
        for name, choice in choices.items():
            label = f"{name} — {choice}"
            if self._choices.get(name) != label:
                self._choices[name] = label
                groups[name].label = label

    def show_html(self, handle: viser.GuiHtmlHandle, content: str) -> None:
        if handle.content != content:
            handle.content = content

    def shown(self, label: str) -> str:
        """The text a readout shows now (for the benchmark; a str is replaced atomically)."""
        return self.readouts.shown(label)

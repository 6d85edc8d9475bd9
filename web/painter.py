"""What the loop draws (loop thread only), read from its state and the simulation's own record
(web/record.py; the viewer keeps no copy of the history): the readouts, status line and job
list (`Painter.readouts`), the footfall, Delta31 and return-map panels with a replayed job's
run (`Painter.gait`), each panel rebuilt only when its inputs changed (`Redraws`), at rates the
loop sets. The bifurcation, atlas, drift-surface and ramp-path panels are web/chart_painter.py's.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable

import viser

from sim_core import return_map_from_series
from sim_core.contract import RETURN_MAP_SKIP
from web import controls, export
from web.d31_svg import d31_svg
from web.footfall_svg import footfall_svg
from web.job_replay import Replay, replay_panel
from web.jobs import JobView, JobWatcher, job_status_html
from web.panel_labels import RAMP_PLOT_EMPTY
from web.panels import Panels
from web.readouts import Readouts
from web.record import d31_since, footfall_bars
from web.return_map_plot import return_map_data
from web.state import LoopConfig, ViewerState


class Redraws:
    """Which inputs each panel was last drawn from: a panel is rebuilt only when they changed
    (an idle plot costs nothing), and the live walk leaves the panels a replayed job's run
    fills alone. Shared by the painters."""

    def __init__(self, state: ViewerState, panels: Panels) -> None:
        self._state, self._panels = state, panels
        self._drawn: dict[int, Hashable] = {}  # per panel handle, the inputs last drawn
        self._replay: Replay | None = None  # the replay the panels were last drawn for

    def replay(self) -> Replay | None:
        """The replay in force, called before drawing: when it changed every panel is drawn
        afresh, a ramp path that a replay filled back to its placeholder."""
        replay = self._state.replaying
        if replay is not self._replay:
            if self._replay is not None and self._replay.ramp is not None:
                self._panels.show_html(self._panels.ramp_plot, RAMP_PLOT_EMPTY)
            self._replay = replay
            self._drawn.clear()
        return replay

    def handle(self, panel: str) -> viser.GuiHtmlHandle:
        """The live panel a replay's `panel` (job_replay.PANELS) is drawn in."""
        p = self._panels
        return {"d31": p.d31, "footfall": p.footfall, "ramp": p.ramp_plot}[panel]

    def changed(self, handle: object, key: Hashable) -> bool:
        """Whether `key`, the inputs a panel is drawn from (the walk, the record's length or
        time, the window), changed since it was last drawn."""
        if self._drawn.get(id(handle)) == key:
            return False
        self._drawn[id(handle)] = key
        return True

    def redraw(self, handle: viser.GuiHtmlHandle, key: Hashable, build: Callable[[], str]) -> None:
        """Rebuild an SVG panel only when its inputs changed, unless a replay fills it."""
        replay = self._replay
        if replay is not None and any(self.handle(p) is handle for p in replay.panels):
            return
        if self.changed(handle, key):
            self._panels.show_html(handle, build())


class Painter:
    """The readouts, the status line, the job list and the gait panels."""

    def __init__(
        self,
        state: ViewerState,
        panels: Panels,
        *,
        jobs: JobWatcher,
        redraws: Redraws,
        config: LoopConfig,
    ) -> None:
        self._state, self._panels, self._jobs = state, panels, jobs
        self._redraws, self._cfg = redraws, config
        self._job_shown: JobView | None = None
        self._jobs_shown: Hashable = None  # the list's version and the replay last shown

    def readouts(
        self, rtf: float | None, stepping_rtf: float | None, frame_hz: float | None
    ) -> None:
        """Controls the loop changed, the readouts and the status line (cheap: a few short
        strings, each sent only when it changed), the job bodies and the job list."""
        state, panels = self._state, self._panels
        ramping = None if state.ramp is None else state.ramp.param
        write, state.write = state.write, {}
        panels.sync(state.playing, ramping, write)
        panels.readouts.show(readouts_of(state, rtf, stepping_rtf, frame_hz))
        ramp_param = ramping or panels.ramp.param_name
        panels.show_choices({
            "speed": controls.speed_label(state.speed) or controls.DEFAULT_SPEED,
            "camera": state.follow,
            "ground": controls.GROUND_LABEL[state.ground],
            "ramp drives": controls.RAMP_LABELS.get(ramp_param, ramp_param),
            "atlas over": panels.atlas_axis,
        })  # fmt: skip
        panels.show_html(panels.job, export.job_html(state.settings(panels.job_inputs())))
        view = self._jobs.view
        if view is not self._job_shown:
            self._job_shown = view
            panels.show_html(panels.job_status, job_status_html(view))
        replay = state.replaying
        key = (self._jobs.version, None if replay is None else replay.job_id)
        if key != self._jobs_shown:  # a job changed, or a replay began or ended
            self._jobs_shown = key
            panels.job_rows.show(self._jobs.views, key[1])

    def gait(self) -> None:
        """The footfall diagram, Delta31 and the return map, each rebuilt only when its inputs
        changed; a replayed job's run first, in the panels it fills."""
        state, panels, redraws = self._state, self._panels, self._redraws
        replay = redraws.replay()
        if replay is not None:
            window = state.footfall_window_s
            for panel in replay.panels:
                handle = redraws.handle(panel)
                if redraws.changed(handle, ("replay", replay.job_id, window)):
                    panels.show_html(handle, replay_panel(replay, panel, window))
        sim, walk = state.sim, state.walk
        gait = sim.gait
        t_now, window = sim.time_s, state.footfall_window_s
        redraws.redraw(
            panels.footfall,
            (walk, t_now, window),
            lambda: footfall_svg(footfall_bars(sim, window), t_now, window),
        )
        w, events, job = state.d31_window_s, sim.d31_events, self._jobs.view
        redraws.redraw(
            panels.d31,
            (walk, len(events), t_now, w, gait, job.id, len(job.d31_series)),
            lambda: d31_svg(
                events if w is None else d31_since(events, t_now - w),
                t_now,
                w,
                gait,
                state.d31_conditions.marks,
                (job.id[:8], job.d31_series) if job.d31_series else None,
            ),
        )
        if redraws.changed(panels.return_map, (walk, len(events), sim.beta)):
            panels.return_map.data = return_map_data(self._return_map())

    def _return_map(self) -> list[tuple[float, float]]:
        """The current run's (Delta31 n, n + 4) pairs, the latest `return_map_len`, built by
        the core's return-map construction (first RETURN_MAP_SKIP of the run dropped)."""
        sim = self._state.sim
        events = sim.d31_events
        recent = events[-(self._cfg.return_map_len + 4) :]
        whole = len(recent) == len(events)
        rm = return_map_from_series(
            sim.beta, [[d for _, d in recent]], lag=4, skip=RETURN_MAP_SKIP if whole else 0
        )
        return list(zip(rm.x.tolist(), rm.y.tolist(), strict=True))


def readouts_of(
    state: ViewerState, rtf: float | None, stepping_rtf: float | None, frame_hz: float | None
) -> Readouts:
    """What the readouts say of the walk now, with the loop's measured rates."""
    sim, ramp = state.sim, state.ramp
    ramp_words = ""
    if ramp is not None:
        elapsed = sim.time_s - state.ramp_t0
        ramp_words = (
            f"{controls.RAMP_LABELS[ramp.param]} {sim.ramp_phase}: {sim.get(ramp.param):.3f} "
            f"({min(elapsed, ramp.duration_s):.0f} of {ramp.duration_s:.0f} s)"
        )
    heading = sim.heading_rad
    return Readouts(
        beta=sim.beta,
        time_s=sim.time_s,
        speed_cm_s=sim.speed_cm_s,
        duty_factor=sim.duty_factor,
        gait=sim.gait,
        d31_now=sim.d31_now,
        rtf=rtf,
        stepping_rtf=stepping_rtf,
        target_speed=state.speed,
        frame_hz=frame_hz,
        ramp=ramp_words,
        error=state.error,
        playing=state.playing,
        body_mass_g=sim.body_mass_g,
        slope_deg=sim.slope_deg,
        heading_deg=None if heading is None else math.degrees(heading),
        ground=state.ground,
        model=state.model_words,
        lag_s=state.clock.lag_s,
    )

"""What each request does to the viewer (loop thread only): the parameters, speed, restarts,
ground, ramps, exports, jobs and loaded settings (web/requests.py says who may ask)."""

from __future__ import annotations

import time

from sim_core import ModelParams, RunSpec, Simulation
from sim_core.contract import EventConditions, provenance
from web import controls, export
from web.job_replay import Replay
from web.panel_labels import RAMP_PLOT_EMPTY
from web.paths import DEFAULT_API_URL
from web.requests import (
    PARAMS,
    CancelJob,
    Export,
    LoadSettings,
    OpenJob,
    ReplayJob,
    Request,
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
    StopReplay,
    SubmitJob,
    SubmitSurface,
)
from web.state import ViewerState


class Dispatch(ViewerState):
    """The requests' effects, and the settings and exports they read."""

    replaying: Replay | None = None  # a done job's run the panels show instead of the walk's

    def apply(self, req: Request) -> None:
        sim = self.sim
        match req:
            case SetParam(name=name, value=v):
                if name not in PARAMS:
                    raise ValueError(f"unknown parameter {name!r}; choose from {PARAMS}")
                if self.ramp is not None and self.ramp.param == name:
                    return  # the ramp drives it (its slider is disabled): a stale request
                self._set_param(name, controls.RAMP_SLIDERS[name].clamp(v))
            case SetSpeed(multiplier=m):
                self.speed = m
                self._clock.reset()
            case SetPlaying(playing=p):
                self.playing = p and self.error is None
            case StepCycle():
                if not self.playing and self.error is None:
                    period = ModelParams().trajectory.swing_duration / (1.0 - sim.beta)  # eq. 2
                    self._step(period, time.perf_counter() + 60.0)
            case SetFollow(mode=m):
                self.scene.set_follow(m)
            case SetDraw3D(on=on):
                self.draw_3d = on
            case SetFootfallWindow(seconds=w):
                self.footfall_window_s = controls.FOOTFALL_WINDOW_S.clamp(w)
            case SetD31Window(seconds=w):
                self.d31_window_s = w
            case Reset(d31_init=d):
                self._stop_ramp()
                self.d31_init = controls.d31_init_value(d)
                sim.reset(d31_init=self.d31_init)
                self._restarted()
                self.panels.show_d31_init(self.d31_init)  # a preset moves its slider
            case SetGround(ground=g):
                if g not in controls.GROUND_LABEL:
                    raise ValueError(
                        f"unknown ground {g!r}; choose from {list(controls.GROUND_LABEL)}"
                    )
                if g == self.ground:
                    return
                self._stop_ramp()
                here = {"beta": sim.beta, "body_mass_g": sim.body_mass_g,
                        "slope_deg": sim.slope_deg, "d31_init": self.d31_init}  # fmt: skip
                self.sim = Simulation(RunSpec(**here), ModelParams.of(ground=g))
                self.ground = g
                self._restarted()
            case StartRamp(ramp=ramp):
                self._stop_ramp()
                self.ramp = ramp
                self._ramp_t0 = sim.time_s
                self._last_ramp = ramp
                sim.start_ramp(ramp)  # the core's ramp driver moves the parameter
                self._write[ramp.param] = ramp.start  # the slider shows the start, once
                self.d31_conditions.start_ramp(sim)  # a new ramp draws a new path
            case StopRamp():
                self._stop_ramp()
            case Export(what=what, send=send):
                name, data = self.export(what)
                send(name, data)
            case SubmitJob(kind=kind):
                s = self.settings()
                bodies = export.jobs(s)
                if kind not in bodies:
                    raise ValueError("set up a ramp first: the hysteresis job runs that ramp")
                self.jobs.submit(s.api_url, bodies[kind])
            case SubmitSurface():
                self.surface_jobs.submit(self.settings().api_url, self.walk_conditions())
            case OpenJob(job_id=job_id):
                if not job_id.strip():
                    raise ValueError("type a job's id into 'job id' first")
                self.jobs.open(self.settings().api_url, job_id)
            case CancelJob(key=key):
                self.jobs.cancel(key)
            case ReplayJob(key=key):
                view = self.jobs.get(key)
                if view is None or view.replay is None:
                    raise ValueError("that job has no run to replay (a done run or hysteresis job)")
                self._replay(view.replay)
            case StopReplay():
                self._replay(None)
            case LoadSettings(settings=s):
                self._load(s)

    def _replay(self, replay: Replay | None) -> None:
        """Show a job's run in the panels it fills (None: the live walk again); every panel
        is drawn afresh, the ramp path back to its placeholder until a live ramp draws it."""
        if self.replaying is not None and self.replaying.ramp is not None:
            self.panels.show_html(self.panels.ramp_plot, RAMP_PLOT_EMPTY)
        self.replaying = replay
        self._drawn.clear()

    def _load(self, s: export.Settings) -> None:
        """A loaded settings file: its ground, parameters and speed, then a restart from its
        initial Delta31; its ramp and job inputs into their boxes (not started)."""
        self._stop_ramp()
        if s.ground != self.ground:
            spec = RunSpec(beta=s.beta, d31_init=s.d31_init)
            self.sim = Simulation(spec, ModelParams.of(ground=s.ground))
            self.ground = s.ground
        for name in PARAMS:
            value = controls.RAMP_SLIDERS[name].clamp(getattr(s, name))
            self._set_param(name, value)
            self._write[name] = value  # the sliders show what was loaded
        self.speed = s.speed
        self.d31_init = controls.d31_init_value(s.d31_init)
        self.sim.reset(d31_init=self.d31_init)
        self._restarted()
        self.panels.show_d31_init(self.d31_init)
        self.panels.load_inputs(s)

    def _restarted(self) -> None:
        """A new walk began (reset or another ground): its record starts over."""
        self.d31_conditions.clear()
        self._walk += 1
        self._clock.reset()
        self.error = None
        self.playing = True

    def _set_param(self, name: str, value: float) -> None:
        getattr(self.sim, f"set_{name}")(value)

    def _stop_ramp(self) -> None:
        """End the ramp where it is; its slider then shows the value the ramp left."""
        if self.ramp is not None:
            self._write[self.ramp.param] = getattr(self.sim, self.ramp.param)
        self.ramp = None
        self.sim.stop_ramp()

    def settings(self) -> export.Settings:
        running = self.ramp is not None
        ramp = self.ramp
        if ramp is None:
            try:
                ramp = self.panels.ramp_settings()
            except (TypeError, ValueError):
                ramp = None
        try:
            duration = min(600.0, max(1.0, float(self.panels.job_duration.value)))
        except (TypeError, ValueError):
            duration = 30.0
        return export.Settings(
            beta=self.sim.beta,
            body_mass_g=self.sim.body_mass_g,
            slope_deg=self.sim.slope_deg,
            d31_init=self.d31_init,
            speed=self.speed,
            time_s=self.sim.time_s,
            ground=self.ground,
            ramp=ramp,
            ramp_running=running,
            ramp_started_at_s=self._ramp_t0 if running else None,
            job_duration_s=duration,
            api_url=str(self.panels.api_url.value).strip() or DEFAULT_API_URL,
        )

    def provenance(self) -> export.Provenance:
        """What makes the walk's numbers (the core's `provenance`: physics version, the
        parameter hash the cache uses, ground, dt), for every export."""
        return provenance(ModelParams.of(ground=self.ground))

    def export(self, what: str) -> tuple[str, bytes]:
        """(file name, content) of one export (web/export.py); loop thread only."""
        stamp, made = f"t{self.sim.time_s:.0f}s", self.provenance()
        if what == "d31":
            events = self.d31_conditions.events(self.sim)
            return f"insect-gait_d31_{stamp}.csv", export.d31_csv(events, made=made)
        if what == "footfall":
            intervals = self.sim.stance_intervals()  # the whole walk since its (re)start
            sim = self.sim
            now = EventConditions(sim.beta, sim.body_mass_g, sim.slope_deg, self.ground)
            events = self.d31_conditions.events(sim)
            data = export.footfall_csv(intervals, events, now, made=made)
            return f"insect-gait_footfall_{stamp}.csv", data
        if what == "ramp":
            path, ramp = self.d31_conditions.ramp_path(self.sim), self._last_ramp
            t0 = self._ramp_t0 if ramp is not None else None
            return f"insect-gait_ramp_{stamp}.csv", export.ramp_csv(path, ramp, t0, made=made)
        if what == "settings":
            data = export.settings_json(self.settings(), made=made)
            return f"insect-gait_settings_{stamp}.json", data
        raise ValueError(f"unknown export {what!r}; choose from {export.EXPORTS}")

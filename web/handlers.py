"""What each request does (loop thread only): a handler per request type, looked up by type.

web/requests.py says who may ask (GUI callbacks queue frozen requests); the loop applies each
with `apply`, which finds the handler registered for the request's type (`@handles`). A
handler is a small function of the viewer's parts it acts on (`Viewer`): most change the
loop's state (web/state.py), a few the panel's inputs or the job links. A request
type without a handler fails the moment it is applied, and a test holds that every one has one.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

from sim_core import ModelParams
from sim_core.contract import EventConditions
from web import controls, export
from web.jobs import JobWatcher
from web.panels import Panels
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
from web.settings_file import JobInputs
from web.state import ViewerState
from web.surface_jobs import SurfaceJobs


class Viewer(Protocol):
    """What the handlers act on: the loop's state and the viewer's parts (web/app.py)."""

    @property
    def state(self) -> ViewerState: ...
    @property
    def panels(self) -> Panels: ...
    @property
    def jobs(self) -> JobWatcher: ...
    @property
    def surface_jobs(self) -> SurfaceJobs: ...
    def step(self, due_s: float, deadline: float) -> float: ...


R = TypeVar("R")
HANDLERS: dict[type, Callable[[Viewer, Any], None]] = {}


def handles(kind: type[R]) -> Callable[[Callable[[Viewer, R], None]], Callable[[Viewer, R], None]]:
    """Register the decorated function as the handler of requests of type `kind`."""

    def register(handler: Callable[[Viewer, R], None]) -> Callable[[Viewer, R], None]:
        if kind in HANDLERS:
            raise RuntimeError(f"{kind.__name__} has a handler already")
        HANDLERS[kind] = handler
        return handler

    return register


def apply(viewer: Viewer, req: Request) -> None:
    """Apply `req` to `viewer` (loop thread) by the handler of its type."""
    HANDLERS[type(req)](viewer, req)


# --- the walk -------------------------------------------------------------------------------
@handles(SetParam)
def _set_param(v: Viewer, req: SetParam) -> None:
    if req.name not in PARAMS:
        raise ValueError(f"unknown parameter {req.name!r}; choose from {PARAMS}")
    ramp = v.state.ramp
    if ramp is not None and ramp.param == req.name:
        return  # the ramp drives it (its slider is disabled): a stale request
    v.state.set(req.name, req.value)


@handles(SetSpeed)
def _set_speed(v: Viewer, req: SetSpeed) -> None:
    v.state.speed = req.multiplier
    v.state.clock.reset()


@handles(SetPlaying)
def _set_playing(v: Viewer, req: SetPlaying) -> None:
    v.state.playing = req.playing and v.state.error is None


@handles(StepCycle)
def _step_cycle(v: Viewer, req: StepCycle) -> None:
    s = v.state
    if not s.playing and s.error is None:
        period = ModelParams().trajectory.swing_duration / (1.0 - s.sim.beta)  # eq. 2
        v.step(period, time.perf_counter() + 60.0)


@handles(Reset)
def _reset(v: Viewer, req: Reset) -> None:
    v.state.restart(req.d31_init)
    v.panels.walk.show_d31_init(v.state.d31_init)  # a preset moves its slider


@handles(SetGround)
def _set_ground(v: Viewer, req: SetGround) -> None:
    if req.ground not in controls.GROUND_LABEL:
        raise ValueError(
            f"unknown ground {req.ground!r}; choose from {list(controls.GROUND_LABEL)}"
        )
    if req.ground != v.state.ground:  # the model's other parameters are kept
        v.state.restart(v.state.d31_init, ground=req.ground)


@handles(StartRamp)
def _start_ramp(v: Viewer, req: StartRamp) -> None:
    v.state.start_ramp(req.ramp)


@handles(StopRamp)
def _stop_ramp(v: Viewer, req: StopRamp) -> None:
    v.state.stop_ramp()


@handles(LoadSettings)
def _load(v: Viewer, req: LoadSettings) -> None:
    """A loaded settings file: its parameters and speed, then a restart on its ground from its
    initial Delta31; its ramp and job inputs into their boxes (not started)."""
    s, state = req.settings, v.state
    state.stop_ramp()
    for name in PARAMS:
        value = controls.RAMP_SLIDERS[name].clamp(getattr(s, name))
        state.set(name, value)
        state.write[name] = value  # the sliders show what was loaded
    state.speed = s.speed
    # its ground, setting and parameters, and every field of its run (phase_reset, ...)
    state.restart(s.d31_init, model=s.choice(), run=s.run)
    v.panels.walk.show_d31_init(state.d31_init)
    v.panels.load(s)


# --- how it is shown ------------------------------------------------------------------------
@handles(SetFollow)
def _set_follow(v: Viewer, req: SetFollow) -> None:
    v.state.follow = controls.camera_mode(req.mode)


@handles(SetDraw3D)
def _set_draw_3d(v: Viewer, req: SetDraw3D) -> None:
    v.state.draw_3d = req.on


@handles(SetFootfallWindow)
def _set_footfall_window(v: Viewer, req: SetFootfallWindow) -> None:
    v.state.footfall_window_s = controls.FOOTFALL_WINDOW_S.clamp(req.seconds)


@handles(SetD31Window)
def _set_d31_window(v: Viewer, req: SetD31Window) -> None:
    v.state.d31_window_s = req.seconds


@handles(ReplayJob)
def _replay(v: Viewer, req: ReplayJob) -> None:
    """A done job's run in the panels it fills (the painter redraws every panel afresh)."""
    view = v.jobs.get(req.key)
    if view is None or view.replay is None:
        raise ValueError("that job has no run to replay (a done run or hysteresis job)")
    v.state.replaying = view.replay


@handles(StopReplay)
def _stop_replay(v: Viewer, req: StopReplay) -> None:
    v.state.replaying = None


# --- files and jobs -------------------------------------------------------------------------
@handles(Export)
def _export(v: Viewer, req: Export) -> None:
    req.send(*export_file(v.state, v.panels.job_inputs(), req.what))


@handles(SubmitJob)
def _submit_job(v: Viewer, req: SubmitJob) -> None:
    s = v.state.settings(v.panels.job_inputs())
    bodies = export.jobs(s)
    if req.kind not in bodies:
        raise ValueError("set up a ramp first: the hysteresis job runs that ramp")
    v.jobs.submit(s.api_url, bodies[req.kind])


@handles(SubmitSurface)
def _submit_surface(v: Viewer, req: SubmitSurface) -> None:
    v.surface_jobs.submit(v.panels.job_inputs().api_url, v.state.conditions(), v.state.model)


@handles(OpenJob)
def _open_job(v: Viewer, req: OpenJob) -> None:
    if not req.job_id.strip():
        raise ValueError("type a job's id into 'job id' first")
    v.jobs.open(v.panels.job_inputs().api_url, req.job_id)


@handles(CancelJob)
def _cancel_job(v: Viewer, req: CancelJob) -> None:
    v.jobs.cancel(req.key)


def export_file(state: ViewerState, inputs: JobInputs, what: str) -> tuple[str, bytes]:
    """(file name, content) of one export (web/export.py) of the walk; loop thread only."""
    sim = state.sim
    stamp, made = f"t{sim.time_s:.0f}s", state.provenance()
    if what == "d31":
        events = state.d31_conditions.events(sim)
        return f"insect-gait_d31_{stamp}.csv", export.d31_csv(events, made=made)
    if what == "footfall":
        intervals = sim.stance_intervals()  # the whole walk since its (re)start
        now = EventConditions(sim.beta, sim.body_mass_g, sim.slope_deg, state.ground)
        events = state.d31_conditions.events(sim)
        data = export.footfall_csv(intervals, events, now, made=made)
        return f"insect-gait_footfall_{stamp}.csv", data
    if what == "ramp":
        path, ramp = state.d31_conditions.ramp_path(sim), state.last_ramp
        t0 = state.ramp_t0 if ramp is not None else None
        return f"insect-gait_ramp_{stamp}.csv", export.ramp_csv(path, ramp, t0, made=made)
    if what == "settings":
        data = export.settings_json(state.settings(inputs), made=made)
        return f"insect-gait_settings_{stamp}.json", data
    raise ValueError(f"unknown export {what!r}; choose from {export.EXPORTS}")

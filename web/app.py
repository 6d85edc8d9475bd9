"""The viewer: one viser server, one shared `Simulation`, one loop thread that owns it.

Threads. viser serves websockets on its own thread and runs GUI callbacks on a pool; those
callbacks only queue requests (web/requests.py). The loop thread is the only code that touches
the simulation: each frame it applies queued requests, steps the physics by the simulated time
the wall clock says is due (at the chosen speed), notes the conditions of the new Delta31
events, and streams poses inside `server.atomic()`. Diagrams and readouts are redrawn at a few
Hz from the simulation's own record (web/record.py; the viewer keeps no copy of the history):
they are read by people, and each redraw is a message to every browser; a panel whose inputs
did not change (a paused run) is not rebuilt.

One simulation for everyone: viser's `server.gui` is shared by all browsers, so sliders already
move for everybody; a simulation per browser would need per-client panels and would multiply
the CPU cost per open tab on a model that barely runs faster than real time.

Nobody watching, nothing simulated: with no browser connected the loop does not step (it would
cost a third of a core for nobody); it waits for viser's client-connect hook and resumes where
it stopped.
"""

from __future__ import annotations

import html
import json
import logging
import math
import threading
import time
from collections import deque
from collections.abc import Callable, Hashable
from dataclasses import dataclass
from pathlib import Path

import viser

from sim_core import ModelParams, RunSpec, Simulation
from sim_core.contract import (
    ATLAS_AXES,
    AXIS_LABEL,
    RETURN_MAP_SKIP,
    DriftSurface,
    FinderOutput,
    Ramp,
    SurfaceAtlas,
    return_map_from_series,
    surface_atlas_file,
)
from web import controls, export
from web.bifurcation import WatchedFile, finder_points
from web.jobs import JobView, JobWatcher, job_status_html
from web.pacing import RateMeter, SimClock
from web.panels import Panels, Readouts
from web.paths import DEFAULT_API_URL, DEFAULT_BIFURCATION, DEFAULT_SURFACE
from web.record import Conditions, D31Conditions, d31_since, footfall_bars
from web.requests import (
    PARAMS,
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
from web.scene import HexapodScene
from web.surface_svg import surface_svg
from web.svg import (
    atlas_svg,
    bifurcation_svg,
    d31_svg,
    footfall_svg,
    ramp_path_svg,
    return_map_svg,
)

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class LoopConfig:
    fps: float = 30.0  # pose streaming rate; ~30 Hz is plenty for a walking insect
    readout_hz: float = 5.0  # the readouts and status line (people read them)
    panel_hz: float = 5.0  # diagrams, at most; less often when drawing them costs more
    draw_share: float = 0.15  # the loop's time the diagrams' drawing may take at most
    shadows: bool = False  # cast shadows in the 3D view (extra render passes every frame)
    chunk_s: float = 0.002  # stepping chunk: ramps and conditions act between chunks
    step_budget: float = 0.8  # share of a frame the stepping may use before we draw anyway
    trail_len: int = 600  # live (beta, Delta31) points kept on the bifurcation panel
    return_map_len: int = 1200  # latest Delta31 pairs on the return map


@dataclass(frozen=True)
class LoopStats:
    """A snapshot for the benchmark and tests (read from any thread; replaced atomically)."""

    frames: int = 0
    sim_s: float = 0.0
    step_wall_s: float = 0.0
    rtf: float | None = None
    stepping_rtf: float | None = None
    frame_hz: float | None = None
    beta: float = controls.BETA.initial
    clients: int = 0
    idle: bool = True  # no browser connected: not simulating


class ViewerApp:
    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8080,
        *,
        spec: RunSpec | None = None,
        config: LoopConfig | None = None,
        bifurcation_path: Path = DEFAULT_BIFURCATION,
        surface_path: Path = DEFAULT_SURFACE,
        api_url: str = DEFAULT_API_URL,
    ) -> None:
        self.cfg = config or LoopConfig()
        self.requests = RequestQueue()
        self.d31_init = controls.d31_init_value(controls.D31_INIT.initial)
        self.sim = Simulation(
            spec
            or RunSpec(
                beta=controls.BETA.initial,
                body_mass_g=controls.BODY_MASS_G.initial,
                slope_deg=controls.SLOPE_DEG.initial,
                d31_init=self.d31_init,
            )
        )
        if spec is not None:
            self.d31_init = spec.d31_init
        self.ground = "constraint"  # `ModelParams.ground` of the running simulation
        self.server = viser.ViserServer(host=host, port=port, label="insect-gait", verbose=False)
        self.scene = HexapodScene(self.server, self.sim.model, shadows=self.cfg.shadows)
        self.panels = Panels(self.server, self.requests)
        if api_url != DEFAULT_API_URL:
            self.panels.api_url.value = api_url  # type: ignore[misc]  # viser types the setter on a subclass
        sim = self.sim
        start = {"beta": sim.beta, "body_mass_g": sim.body_mass_g, "slope_deg": sim.slope_deg}
        self.panels.sync_controls(True, None, start)
        self.footfall_window_s = controls.FOOTFALL_WINDOW_S.initial
        self.d31_conditions = D31Conditions()  # what the core's Delta31 events happened under
        self._walk = 0  # bumps when the walk starts over: its record is a new one
        self._drawn: dict[int, Hashable] = {}  # per panel handle, the inputs last drawn
        self.d31_window_s: float | None = None  # None: the whole run
        self.bifurcation_path = bifurcation_path
        self.bifurcation = WatchedFile(bifurcation_path, FinderOutput, "finder results")
        self.atlases = {
            (axis, g): WatchedFile(
                surface_atlas_file(bifurcation_path.parent, axis, g), SurfaceAtlas, "atlas"
            )
            for axis in ATLAS_AXES
            for g in controls.GROUND_LABEL
        }
        self.surface = WatchedFile(surface_path, DriftSurface, "drift surface")
        self.playing = True
        self.draw_3d = True  # stream poses (SetDraw3D)
        self.speed: float | None = controls.speed_value(controls.DEFAULT_SPEED)
        self.ramp: Ramp | None = None
        self._ramp_t0 = 0.0
        self._ramp_phase = ""
        self._last_ramp: Ramp | None = None  # the latest ramp, for its path's export
        self._write: dict[str, float] = {}  # values the loop sets into sliders at next redraw
        self.error: str | None = None
        self.jobs = JobWatcher()  # the job submitted or opened from this viewer
        self._job_shown: JobView | None = None
        # (wall time.time(), request) of the latest requests applied: the input latency a
        # benchmark reads against the browser's key and click times (same clock)
        self.applied: deque[tuple[float, Request]] = deque(maxlen=256)
        self.stats = LoopStats()
        self._clock = SimClock()
        self._stop = threading.Event()
        self._wake = threading.Event()  # set by viser's connect hook: a browser arrived
        self._thread: threading.Thread | None = None
        self.server.on_client_connect(self._on_connect)
        self.server.on_client_disconnect(self._on_connect)

    def _on_connect(self, client: viser.ClientHandle) -> None:
        """viser's connect/disconnect hook (its thread pool): only wakes the loop."""
        self._wake.set()

    @property
    def port(self) -> int:
        return self.server.get_port()

    # --- lifecycle ----------------------------------------------------------------------------
    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="sim-loop", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
        self.server.stop()

    def serve_forever(self) -> None:
        self.start()
        try:
            while self._thread is not None and self._thread.is_alive():
                self._thread.join(timeout=0.5)
        except KeyboardInterrupt:
            pass
        finally:
            self.stop()

    # --- requests (loop thread) ---------------------------------------------------------------
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
                    period = ModelParams().swing_duration / (1.0 - sim.beta)  # eq. 2
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
                self.sim = Simulation(RunSpec(**here), ModelParams(ground=g))
                self.ground = g
                self._restarted()
            case StartRamp(ramp=ramp):
                self._stop_ramp()
                self.ramp = ramp
                self._ramp_t0 = sim.time_s
                self._last_ramp = ramp
                self._ramp_phase = controls.ramp_phase(ramp, 0.0)
                self._set_param(ramp.param, ramp.start)
                self._write[ramp.param] = ramp.start  # the slider shows the start, once
                self.d31_conditions.start_ramp()  # a new ramp draws a new path
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
            case OpenJob(job_id=job_id):
                if not job_id.strip():
                    raise ValueError("type a job's id into 'job id' first")
                self.jobs.open(self.settings().api_url, job_id)
            case LoadSettings(settings=s):
                self._load(s)

    def _load(self, s: export.Settings) -> None:
        """A loaded settings file: its ground, parameters and speed, then a restart from its
        initial Delta31; its ramp and job inputs into their boxes (not started)."""
        self._stop_ramp()
        if s.ground != self.ground:
            spec = RunSpec(beta=s.beta, d31_init=s.d31_init)
            self.sim = Simulation(spec, ModelParams(ground=s.ground))
            self.ground = s.ground
        for name in PARAMS:
            value = controls.RAMP_SLIDERS[name].clamp(getattr(s, name))
            self._set_param(name, value)
            self._write[name] = value  # the sliders show what was loaded
        self.speed = s.speed
        self.d31_init = controls.d31_init_value(s.d31_init)
        self.sim.reset(d31_init=self.d31_init)
        self._restarted()
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
        self._ramp_phase = ""

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

    def export(self, what: str) -> tuple[str, bytes]:
        """(file name, content) of one export (web/export.py); loop thread only."""
        stamp = f"t{self.sim.time_s:.0f}s"
        events = self.sim.d31_events
        if what == "d31":
            return f"insect-gait_d31_{stamp}.csv", export.d31_csv(
                self.d31_conditions.events(events)
            )
        if what == "footfall":
            intervals = self.sim.stance_intervals()  # the whole walk since its (re)start
            return f"insect-gait_footfall_{stamp}.csv", export.footfall_csv(intervals)
        if what == "ramp":
            path, ramp = self.d31_conditions.ramp_path(events), self._last_ramp
            data = export.ramp_csv(path, ramp, self._ramp_t0 if ramp is not None else None)
            return f"insect-gait_ramp_{stamp}.csv", data
        if what == "settings":
            return f"insect-gait_settings_{stamp}.json", export.settings_json(self.settings())
        raise ValueError(f"unknown export {what!r}; choose from {export.EXPORTS}")

    # --- the loop -----------------------------------------------------------------------------
    def _run(self) -> None:
        cfg = self.cfg
        period = 1.0 / cfg.fps
        rtf, step_rtf, fps = RateMeter(), RateMeter(), RateMeter()
        sim_total = step_wall_total = 0.0
        frames = 0
        last = time.perf_counter()
        next_panel = next_bif = next_readout = 0.0
        while not self._stop.is_set():
            clients = len(self.server.get_clients())
            if clients == 0:
                # nobody watching: do not simulate; sleep until a browser connects
                self.stats = LoopStats(
                    frames, sim_total, step_wall_total, None, None, None, self.sim.beta, 0, True
                )
                self._wake.wait(0.5)
                self._wake.clear()
                last = time.perf_counter()
                self._clock.reset()
                rtf.reset()
                step_rtf.reset()
                fps.reset()
                continue
            t_frame = time.perf_counter()
            self._apply_pending()
            wall_dt, last = t_frame - last, t_frame
            if self.playing and self.error is None:
                due = math.inf if self.speed is None else self._clock.tick(wall_dt, self.speed)
                deadline = t_frame + cfg.step_budget * period
                t_step = time.perf_counter()
                advanced = self._step(due, deadline)
                step_wall_total += time.perf_counter() - t_step
                sim_total += advanced
                if self.speed is not None:
                    self._clock.paid(advanced)
            self._apply_pending()  # what came while stepping, before it is drawn
            now = time.perf_counter()
            rtf.add(now, sim_total)
            step_rtf.add(step_wall_total, sim_total)
            if self.draw_3d:
                data = self.sim.data  # kinematics computed once per frame
                self.scene.update(data, self.sim.stance, self.sim.slope_deg, self.sim.heading_rad)
                frames += 1
            fps.add(now, frames)
            if now >= next_readout:
                next_readout = now + 1.0 / cfg.readout_hz
                self._draw_readouts(rtf.rate, step_rtf.rate, fps.rate)
            # the diagrams: at panel_hz, or less often when drawing them costs more than
            # DRAW_SHARE of the loop's time (a slow machine keeps stepping and answering)
            if now >= next_panel:
                cost = self._timed(self._draw_panels)
                next_panel = now + max(1.0 / cfg.panel_hz, cost / cfg.draw_share)
            if now >= next_bif:
                cost = self._timed(self._draw_bifurcation)
                next_bif = now + max(2.0 / cfg.panel_hz, cost / cfg.draw_share)
            self.stats = LoopStats(
                frames,
                sim_total,
                step_wall_total,
                rtf.rate,
                step_rtf.rate,
                fps.rate,
                self.sim.beta,
                clients,
                False,
            )
            # until the next frame: requests are applied the moment they arrive
            while not self._stop.is_set():
                left = t_frame + period - time.perf_counter()
                if left <= 0:
                    break
                if self.requests.wait(min(left, 0.05)):
                    self._apply_pending()

    def _apply_pending(self) -> None:
        """Apply every queued request now (loop thread), noting when (`applied`)."""
        for req in self.requests.drain():
            try:
                self.apply(req)
            except Exception as exc:  # a bad request must not kill the viewer
                log.exception("request %r failed", req)
                self.error = f"{type(req).__name__} failed: {exc}"
            self.applied.append((time.time(), req))

    @staticmethod
    def _timed(draw: Callable[[], None]) -> float:
        t0 = time.perf_counter()
        draw()
        return time.perf_counter() - t0

    def _step(self, due: float, deadline: float) -> float:
        """Advance in chunks until `due` simulated seconds are done or the frame budget is spent."""
        sim, chunk = self.sim, self.cfg.chunk_s
        advanced = 0.0
        while due - advanced >= chunk * 0.5 and time.perf_counter() < deadline:
            if self.requests.pending():  # a person's input waits no longer than one slice
                speed = self.speed
                self._apply_pending()
                if not self.playing or self.error is not None or self.speed != speed:
                    break
                sim = self.sim  # a reset or another ground may have replaced it
            if self.ramp is not None:
                elapsed = sim.time_s - self._ramp_t0
                self._ramp_phase = controls.ramp_phase(self.ramp, elapsed)
                if self._ramp_phase == "done":
                    self._set_param(self.ramp.param, self.ramp.start)
                    self._stop_ramp()
                else:
                    self._set_param(self.ramp.param, self.ramp.value(elapsed))
            t0 = sim.time_s
            try:
                sim.advance(chunk)
            except Exception as exc:  # diverged: stop and say so, never show wrong numbers
                log.warning("simulation stopped: %s", exc)
                self.error = str(exc)
                self.playing = False
                break
            advanced += sim.time_s - t0
            # the new Delta31 events happened under the parameters (and ramp phase) just used
            param = self.ramp.param if self.ramp is not None and self._ramp_phase else ""
            now = Conditions(sim.beta, sim.body_mass_g, sim.slope_deg, self._ramp_phase, param)
            self.d31_conditions.note(sim.d31_events, now)
        return advanced

    def _draw_readouts(
        self, rtf: float | None, stepping_rtf: float | None, frame_hz: float | None
    ) -> None:
        """Controls the loop changed, the readouts and the status line (cheap: a few short
        strings, each sent only when it changed)."""
        sim = self.sim
        ramp = ""
        if self.ramp is not None:
            r = self.ramp
            elapsed = sim.time_s - self._ramp_t0
            value = getattr(sim, r.param)
            ramp = (
                f"{controls.RAMP_LABELS[r.param]} {self._ramp_phase}: {value:.3f} "
                f"({min(elapsed, r.duration_s):.0f} of {r.duration_s:.0f} s)"
            )
        write, self._write = self._write, {}
        self.panels.sync_controls(
            self.playing, None if self.ramp is None else self.ramp.param, write
        )
        gait = sim.gait
        heading = sim.heading_rad
        self.panels.show_readouts(
            Readouts(
                beta=sim.beta,
                time_s=sim.time_s,
                speed_cm_s=sim.speed_cm_s,
                duty_factor=sim.duty_factor,
                gait=gait,
                d31_now=sim.d31_now,
                rtf=rtf,
                stepping_rtf=stepping_rtf,
                target_speed=self.speed,
                frame_hz=frame_hz,
                ramp=ramp,
                error=self.error,
                playing=self.playing,
                body_mass_g=sim.body_mass_g,
                slope_deg=sim.slope_deg,
                heading_deg=None if heading is None else math.degrees(heading),
                ground=self.ground,
                lag_s=self._clock.lag_s,
            )
        )
        speed = controls.speed_label(self.speed) or controls.DEFAULT_SPEED
        ramp_param = self.ramp.param if self.ramp is not None else self.panels.ramp_param_name
        self.panels.show_choices(
            {
                "speed": speed,
                "camera": self.scene.follow,
                "ground": controls.GROUND_LABEL[self.ground],
                "ramp drives": controls.RAMP_LABELS.get(ramp_param, ramp_param),
                "atlas over": self.panels.atlas_axis,
            }
        )
        self.panels.show_html(self.panels.job, job_html(self.settings()))
        view = self.jobs.view
        if view is not self._job_shown:
            self._job_shown = view
            self.panels.show_html(self.panels.job_status, job_status_html(view))

    def _draw_panels(self) -> None:
        """The footfall diagram, Delta31 and the return map, each rebuilt only when its inputs
        changed."""
        sim = self.sim
        gait = sim.gait
        t_now, window = sim.time_s, self.footfall_window_s
        self._redraw(
            self.panels.footfall,
            (self._walk, t_now, window),
            lambda: footfall_svg(footfall_bars(sim, window), t_now, window),
        )
        w, events, job = self.d31_window_s, sim.d31_events, self.jobs.view
        self._redraw(
            self.panels.d31,
            (self._walk, len(events), t_now, w, gait, job.id, len(job.d31_series)),
            lambda: d31_svg(
                events if w is None else d31_since(events, t_now - w),
                t_now,
                w,
                gait,
                self.d31_conditions.marks,
                (job.id[:8], job.d31_series) if job.d31_series else None,
            ),
        )
        self._redraw(
            self.panels.return_map,
            (self._walk, len(events), sim.beta),
            lambda: return_map_svg(self._return_map()),
        )

    def _redraw(self, handle: viser.GuiHtmlHandle, key: Hashable, build: Callable[[], str]) -> None:
        """Rebuild a panel only when `key`, the inputs it is drawn from, changed (the walk, the
        record's length or time, the window): an idle plot costs nothing."""
        if self._drawn.get(id(handle)) != key:
            self._drawn[id(handle)] = key
            self.panels.show_html(handle, build())

    def _return_map(self) -> list[tuple[float, float]]:
        """The current run's (Delta31 n, n + 4) pairs, the latest `return_map_len`, built by
        the core's return-map construction (first RETURN_MAP_SKIP of the run dropped)."""
        events = self.sim.d31_events
        recent = events[-(self.cfg.return_map_len + 4) :]
        whole = len(recent) == len(events)
        rm = return_map_from_series(
            self.sim.beta, [[d for _, d in recent]], lag=4, skip=RETURN_MAP_SKIP if whole else 0
        )
        return list(zip(rm.x.tolist(), rm.y.tolist(), strict=True))

    def _draw_bifurcation(self) -> None:
        self._draw_ramp_path()
        finder, note = self.bifurcation.get()
        events = self.sim.d31_events
        trail = self.d31_conditions.events(events, -self.cfg.trail_len)
        live = (self.sim.beta, events[-1][1] if events else None)
        self.panels.show_html(
            self.panels.bifurcation,
            bifurcation_svg(
                None if finder is None else finder_points(finder),
                note,
                trail,
                live,
                (controls.BETA.lo, controls.BETA.hi),
                self.d31_conditions.ramp_path(events) if self._ramp_draws_on_beta() else [],
            ),
        )
        axis = self.panels.atlas_axis if self.panels.atlas_axis in ATLAS_AXES else "mass"
        atlas, anote = self.atlases[(axis, self.ground)].get()
        value = self.sim.body_mass_g if axis == "mass" else self.sim.slope_deg
        self.panels.show_html(
            self.panels.atlas,
            atlas_svg(
                atlas,
                anote,
                axis,
                AXIS_LABEL.get(axis, axis),
                (self.sim.beta, value),
                (controls.BETA.lo, controls.BETA.hi),
            ),
        )
        surface, snote = self.surface.get()
        # the map (~80 kB of SVG) is rebuilt only when the file changes or the live point
        # enters another cell of the surface's grid (0.005 in beta, 0.05 rad): a walk that
        # drifts slowly costs the browser a redraw every few seconds, not every 0.4 s
        d31 = live[1]
        cell = (round(self.sim.beta / 0.005), None if d31 is None else round(d31 / 0.05))
        beta_range = (controls.BETA.lo, controls.BETA.hi)
        self._redraw(
            self.panels.surface,
            (self.surface.version, cell, beta_range),
            lambda: surface_svg(surface, snote, live, beta_range),
        )

    def _draw_ramp_path(self) -> None:
        """The latest ramp's path on its own axes (the ramped parameter across), as it goes."""
        ramp = self._last_ramp
        if ramp is None:
            return
        path = self.d31_conditions.ramp_path(self.sim.d31_events)
        rng = controls.RAMP_SLIDERS[ramp.param]
        a, b = sorted((ramp.start, ramp.turn))
        pad = 0.1 * (b - a) or rng.step
        value_range = (max(rng.lo, a - pad), min(rng.hi, b + pad))
        self._redraw(
            self.panels.ramp_plot,
            (self._walk, ramp, len(path)),
            lambda: ramp_path_svg(
                path, ramp.param, controls.RAMP_LABELS.get(ramp.param, ramp.param), value_range
            ),
        )

    def _ramp_draws_on_beta(self) -> bool:
        """A ramp's path goes on the (beta, Delta31) panel when it ramped beta."""
        return self._last_ramp is not None and self._last_ramp.param == "beta"


def job_html(s: export.Settings) -> str:
    """The current settings as REST job bodies to copy, with the curl line and the URL."""
    url = s.api_url.rstrip("/")
    parts = [
        f'<div data-job-url="{html.escape(url)}/v1/jobs" style="font-size:0.8em">',
        f"<b>POST</b> <code>{html.escape(url)}/v1/jobs</code> "
        f'(<a href="{html.escape(url)}/docs" target="_blank">API docs</a>)',
    ]
    for kind, body in export.jobs(s).items():
        text = json.dumps(body, indent=1)
        parts.append(
            f"<div>a <b>{kind}</b> job{' (the ramp set up above)' if kind == 'hysteresis' else ''}:"
            f'</div><pre data-job="{kind}" style="white-space:pre-wrap;user-select:all;'
            f'margin:2px 0;padding:3px;background:#f4f4f4">{html.escape(text)}</pre>'
            f'<pre style="white-space:pre-wrap;user-select:all;margin:2px 0;font-size:0.9em">'
            f"{html.escape(export.curl(url, body))}</pre>"
        )
    parts.append("</div>")
    return "".join(parts)

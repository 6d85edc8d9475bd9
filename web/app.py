"""The viewer: one viser server, one shared `Simulation`, one loop thread that owns it.

Threads. viser serves websockets on its own thread and runs GUI callbacks on a pool; those
callbacks only queue requests (web/requests.py). The loop thread is the only code that touches
the simulation: each frame it applies queued requests, steps the physics by the simulated time
the wall clock says is due (at the chosen speed), samples stance for the footfall diagram, and
streams poses inside `server.atomic()`. Diagrams and readouts are redrawn at a few Hz: they are
read by people, and each redraw is a message to every browser.

One simulation for everyone: viser's `server.gui` is shared by all browsers, so sliders already
move for everybody; a simulation per browser would need per-client panels and would multiply
the CPU cost per open tab on a model that barely runs faster than real time.

Nobody watching, nothing simulated: with no browser connected the loop does not step (it would
cost a third of a core for nobody); it waits for viser's client-connect hook and resumes where
it stopped.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import viser

from sim_core import RunSpec, Simulation
from web import controls
from web.bifurcation import load_bifurcation
from web.footfall import D31Trace, FootfallBuffer
from web.heading import HeadingSpeed
from web.pacing import RateMeter, SimClock
from web.panels import Panels, Readouts
from web.paths import DEFAULT_BIFURCATION
from web.requests import (
    Request,
    RequestQueue,
    Reset,
    SetBeta,
    SetBodyMass,
    SetFollow,
    SetFootfallWindow,
    SetPlaying,
    SetSlope,
    SetSpeed,
    StartRamp,
    StopRamp,
)
from web.scene import HexapodScene
from web.svg import bifurcation_svg, d31_svg, footfall_svg

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class LoopConfig:
    fps: float = 30.0  # pose streaming rate; ~30 Hz is plenty for a walking insect
    panel_hz: float = 5.0  # diagrams and readouts
    chunk_s: float = 0.002  # stance sampling step: a swing lasts 34 ms, a frame 33 ms
    step_budget: float = 0.8  # share of a frame the stepping may use before we draw anyway
    footfall_buffer_s: float = 3.0  # kept; the diagram shows the window the user chose in it
    d31_window_s: float = 30.0
    trail_len: int = 600  # live (beta, Delta31) points kept on the bifurcation panel


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
    ) -> None:
        self.cfg = config or LoopConfig()
        self.requests = RequestQueue()
        self.sim = Simulation(
            spec
            or RunSpec(
                beta=controls.BETA.initial,
                body_mass_g=controls.BODY_MASS_G.initial,
                slope_deg=controls.SLOPE_DEG.initial,
                d31_init=controls.d31_init_value(controls.D31_INIT.initial),
            )
        )
        self.server = viser.ViserServer(host=host, port=port, label="insect-gait", verbose=False)
        self.scene = HexapodScene(self.server, self.sim.model)
        self.panels = Panels(self.server, self.requests)
        self.panels.sync_controls(self.sim.beta, True, False)
        self.footfall = FootfallBuffer(self.cfg.footfall_buffer_s)
        self.footfall_window_s = controls.FOOTFALL_WINDOW_S.initial
        self.d31 = D31Trace()
        self.heading = HeadingSpeed()
        self.bifurcation_path = bifurcation_path
        self._bif_mtime: float | None = -1.0
        self._bif: tuple[dict[str, list[tuple[float, float]]] | None, str] = (None, "")
        self.playing = True
        self.speed: float | None = controls.speed_value(controls.DEFAULT_SPEED)
        self.ramp: controls.BetaRamp | None = None
        self._ramp_t0 = 0.0
        self._ramp_moved_beta = False  # the loop moved beta since the slider last showed it
        self.error: str | None = None
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
            case SetBeta(value=v):
                self.ramp = None  # a hand on the slider overrides the ramp
                sim.set_beta(controls.beta_value(v))
            case SetBodyMass(grams=g):
                sim.set_body_mass_g(controls.body_mass_g_value(g))
            case SetSlope(degrees=d):
                sim.set_slope_deg(controls.slope_deg_value(d))
            case SetSpeed(multiplier=m):
                self.speed = m
                self._clock.reset()
            case SetPlaying(playing=p):
                self.playing = p and self.error is None
            case SetFollow(mode=m):
                self.scene.set_follow(m)
            case SetFootfallWindow(seconds=w):
                self.footfall_window_s = min(
                    self.cfg.footfall_buffer_s, controls.FOOTFALL_WINDOW_S.clamp(w)
                )
            case Reset(d31_init=d):
                self.ramp = None
                sim.reset(d31_init=controls.d31_init_value(d))
                self.footfall.clear()
                self.d31.clear()
                self.heading.clear()
                self._clock.reset()
                self.error = None
                self.playing = True
            case StartRamp(rate_per_s=r):
                self.ramp = controls.BetaRamp(start=sim.beta, rate_per_s=max(1e-4, r))
                self._ramp_t0 = sim.time_s
                self.d31.ramp_path.clear()  # a new ramp draws a new path
            case StopRamp():
                self.ramp = None

    # --- the loop -----------------------------------------------------------------------------
    def _run(self) -> None:
        cfg = self.cfg
        period = 1.0 / cfg.fps
        rtf, step_rtf, fps = RateMeter(), RateMeter(), RateMeter()
        sim_total = step_wall_total = 0.0
        frames = 0
        last = time.perf_counter()
        next_panel = next_bif = 0.0
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
            for req in self.requests.drain():
                try:
                    self.apply(req)
                except Exception as exc:  # a bad request must not kill the viewer
                    log.exception("request %r failed", req)
                    self.error = f"{type(req).__name__} failed: {exc}"
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
            now = time.perf_counter()
            rtf.add(now, sim_total)
            step_rtf.add(step_wall_total, sim_total)
            data = self.sim.data  # kinematics computed once per frame, for all readers
            self.heading.add(self.sim.time_s, data.qpos[0:3], data.qpos[3:7])
            self.scene.update(data, self.sim.stance, self.sim.slope_deg, self.heading.heading_rad)
            frames += 1
            fps.add(now, frames)
            if now >= next_panel:
                next_panel = now + 1.0 / cfg.panel_hz
                self._draw_panels(rtf.rate, step_rtf.rate, fps.rate)
            if now >= next_bif:
                next_bif = now + 2.0 / cfg.panel_hz
                self._draw_bifurcation()
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
            self._stop.wait(max(0.0, t_frame + period - time.perf_counter()))

    def _step(self, due: float, deadline: float) -> float:
        """Advance in chunks until `due` simulated seconds are done or the frame budget is spent."""
        sim, chunk = self.sim, self.cfg.chunk_s
        advanced = 0.0
        while due - advanced >= chunk * 0.5 and time.perf_counter() < deadline:
            direction = ""
            if self.ramp is not None:
                elapsed = sim.time_s - self._ramp_t0
                sim.set_beta(self.ramp.beta_at(elapsed))
                self._ramp_moved_beta = True
                direction = self.ramp.direction_at(elapsed)
                if direction == "done":
                    self.ramp = None
                    direction = ""
            t0 = sim.time_s
            try:
                sim.advance(chunk)
            except Exception as exc:  # diverged: stop and say so, never show wrong numbers
                log.warning("simulation stopped: %s", exc)
                self.error = str(exc)
                self.playing = False
                break
            advanced += sim.time_s - t0
            # every control period of the core's own history, not one sample per chunk
            for t, stance in zip(*sim.footfall_since(self.footfall.t_now), strict=True):
                self.footfall.append(float(t), stance)
            # Delta31 events with the beta (and ramp direction) in force when they happened
            self.d31.sync(sim.d31_events, sim.beta, direction)
        return advanced

    def _draw_panels(
        self, rtf: float | None, stepping_rtf: float | None, frame_hz: float | None
    ) -> None:
        sim, cfg = self.sim, self.cfg
        ramp = ""
        if self.ramp is not None:
            direction = self.ramp.direction_at(sim.time_s - self._ramp_t0)
            ramp = f"{direction}, β = {sim.beta:.3f}"
        # the slider shows beta only when the loop moved it (the ramp), never a person's input
        moved = self._ramp_moved_beta
        self._ramp_moved_beta = False
        self.panels.sync_controls(sim.beta if moved else None, self.playing, self.ramp is not None)
        gait = sim.gait
        heading = self.heading.heading_rad
        self.panels.show_readouts(
            Readouts(
                beta=sim.beta,
                time_s=sim.time_s,
                speed_cm_s=self.heading.speed_cm_s,
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
            )
        )
        t_now = sim.time_s
        self.panels.show_html(
            self.panels.footfall,
            footfall_svg(self.footfall.bars(), t_now, self.footfall_window_s),
        )
        self.panels.show_html(
            self.panels.d31,
            d31_svg(self.d31.recent(t_now - cfg.d31_window_s), t_now, cfg.d31_window_s, gait),
        )

    def _draw_bifurcation(self) -> None:
        path = self.bifurcation_path
        try:
            mtime: float | None = path.stat().st_mtime
        except OSError:
            mtime = None
        if mtime != self._bif_mtime:  # results appear (or change) while the viewer runs
            self._bif_mtime = mtime
            self._bif = load_bifurcation(path)
        cached, note = self._bif
        trail = list(self.d31.events)[-self.cfg.trail_len :]
        last = self.d31.last
        live = (self.sim.beta, last.d31 if last is not None else None)
        self.panels.show_html(
            self.panels.bifurcation,
            bifurcation_svg(
                cached,
                note,
                trail,
                live,
                (controls.BETA.lo, controls.BETA.hi),
                list(self.d31.ramp_path),
            ),
        )

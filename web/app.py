"""The viewer: one viser server, one shared `Simulation`, one loop thread that owns it.

Threads. viser serves websockets on its own thread and runs GUI callbacks on a pool; those
callbacks only queue requests (web/requests.py). The loop thread is the only code that touches
the simulation: each frame it applies queued requests, steps the physics by the simulated time
the wall clock says is due (at the chosen speed), notes the conditions of the new Delta31
events, and streams poses inside `server.atomic()`. Diagrams and readouts are redrawn at a few
Hz from the simulation's own record (web/record.py; the viewer keeps no copy of the history):
they are read by people, and each redraw is a message to every browser; a panel whose inputs
did not change (a paused run) is not rebuilt.

Parts, composed here (as mjlab's viewer composes its scene and overlays): the loop's small
state (web/state.py: the walk and how it is shown), the 3D scene (web/scene.py), the panels
(web/panels.py, themselves of parts), the request handlers (web/handlers.py: one per request
type, looked up by type), the painters (web/painter.py, web/chart_painter.py) and the job
links (web/jobs.py, web/surface_jobs.py). None of them inherits from another.

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
from collections import deque
from collections.abc import Callable
from pathlib import Path

import viser

from sim_core import RunSpec
from sim_core.contract import ModelChoice
from web import handlers
from web.chart_painter import ChartPainter
from web.frame_cap import install_frame_cap
from web.jobs import JobWatcher
from web.painter import Painter, Redraws
from web.panels import Panels
from web.paths import DEFAULT_API_URL, DEFAULT_BIFURCATION, DEFAULT_SURFACE
from web.requests import Request, RequestQueue
from web.scene import HexapodScene
from web.state import LoopConfig, LoopStats, RateMeter, ViewerState
from web.surface_jobs import SurfaceJobs

log = logging.getLogger(__name__)

__all__ = ["LoopConfig", "LoopStats", "ViewerApp"]


class ViewerApp:
    """The viewer: its parts, its lifecycle and its loop."""

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8080,
        *,
        spec: RunSpec | None = None,
        model: ModelChoice | None = None,
        config: LoopConfig | None = None,
        bifurcation_path: Path = DEFAULT_BIFURCATION,
        surface_path: Path = DEFAULT_SURFACE,
        api_url: str = DEFAULT_API_URL,
    ) -> None:
        self.cfg = cfg = config or LoopConfig()
        self.requests = RequestQueue()
        self.state = state = ViewerState.of(spec, model)
        self.server = viser.ViserServer(host=host, port=port, label="insect-gait", verbose=False)
        self.scene = HexapodScene(self.server, state.sim.model, shadows=cfg.shadows)
        install_frame_cap(self.server, cfg.software_fps)
        self.panels = Panels(self.server, self.requests, cfg.software_fps)
        if api_url != DEFAULT_API_URL:
            self.panels.api_url.value = api_url  # type: ignore[misc]  # viser types the setter on a subclass
        self.panels.sync(True, None, {name: state.sim.get(name) for name in handlers.PARAMS})
        self.jobs = JobWatcher()  # the jobs submitted or opened from this viewer
        self.surface_jobs = SurfaceJobs()
        redraws = Redraws(state, self.panels)
        self.painter = Painter(state, self.panels, jobs=self.jobs, redraws=redraws, config=cfg)
        self.charts = ChartPainter(state, self.panels, surface_jobs=self.surface_jobs,
                                   redraws=redraws, config=cfg, bifurcation_path=bifurcation_path,
                                   surface_path=surface_path)  # fmt: skip
        # (wall time.time(), request) of the latest requests applied: the input latency a
        # benchmark reads against the browser's key and click times (same clock)
        self.applied: deque[tuple[float, Request]] = deque(maxlen=256)
        self.stats = LoopStats()
        self._stop = threading.Event()
        self._wake = threading.Event()  # set by viser's connect hook: a browser arrived
        self._thread: threading.Thread | None = None
        self.server.on_client_connect(self._on_connect)
        self.server.on_client_disconnect(self._on_connect)

    @property
    def port(self) -> int:
        return self.server.get_port()

    def _on_connect(self, client: viser.ClientHandle) -> None:
        """viser's connect/disconnect hook (its thread pool): only wakes the loop."""
        self._wake.set()

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

    # --- the loop -----------------------------------------------------------------------------
    def apply(self, req: Request) -> None:
        """Apply one request now (loop thread): the handler of its type (web/handlers.py)."""
        handlers.apply(self, req)

    def _run(self) -> None:
        cfg, state = self.cfg, self.state
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
                    frames, sim_total, step_wall_total, None, None, None, state.sim.beta, 0, True
                )
                self._wake.wait(0.5)
                self._wake.clear()
                last = time.perf_counter()
                state.clock.reset()
                for meter in (rtf, step_rtf, fps):
                    meter.reset()
                continue
            t_frame = time.perf_counter()
            self._apply_pending()
            wall_dt, last = t_frame - last, t_frame
            if state.playing and state.error is None:
                speed = state.speed
                due = math.inf if speed is None else state.clock.tick(wall_dt, speed)
                t_step = time.perf_counter()
                advanced = self.step(due, t_frame + cfg.step_budget * period)
                step_wall_total += time.perf_counter() - t_step
                sim_total += advanced
                if speed is not None:
                    state.clock.paid(advanced)
            self._apply_pending()  # what came while stepping, before it is drawn
            now = time.perf_counter()
            rtf.add(now, sim_total)
            step_rtf.add(step_wall_total, sim_total)
            if state.draw_3d:
                sim = state.sim
                self.scene.update(sim.data, sim.stance, slope_deg=sim.slope_deg,
                                  heading_rad=sim.heading_rad, follow=state.follow)  # fmt: skip
                frames += 1
            fps.add(now, frames)
            if now >= next_readout:
                next_readout = now + 1.0 / cfg.readout_hz
                self.painter.readouts(rtf.rate, step_rtf.rate, fps.rate)
            # the diagrams: at panel_hz, or less often when drawing them costs more than
            # DRAW_SHARE of the loop's time (a slow machine keeps stepping and answering)
            if now >= next_panel:
                cost = _timed(self.painter.gait)
                next_panel = now + max(1.0 / cfg.panel_hz, cost / cfg.draw_share)
            if now >= next_bif:
                cost = _timed(self.charts.draw)
                next_bif = now + max(2.0 / cfg.panel_hz, cost / cfg.draw_share)
            self.stats = LoopStats(frames, sim_total, step_wall_total, rtf.rate, step_rtf.rate,
                                   fps.rate, state.sim.beta, clients, False)  # fmt: skip
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
                self.state.error = f"{type(req).__name__} failed: {exc}"
            self.applied.append((time.time(), req))

    def step(self, due_s: float, deadline: float) -> float:
        """Advance the walk in chunks until `due_s` simulated seconds are done or
        `time.perf_counter()` passes `deadline` (loop thread; `StepCycle` asks for one
        cycle); the simulated seconds advanced."""
        state, chunk = self.state, self.cfg.chunk_s
        sim = state.sim
        advanced = 0.0
        while due_s - advanced >= chunk * 0.5 and time.perf_counter() < deadline:
            if self.requests.pending():  # a person's input waits no longer than one slice
                speed = state.speed
                self._apply_pending()
                if not state.playing or state.error is not None or state.speed != speed:
                    break
                sim = state.sim  # a reset or another ground may have replaced it
            t0 = sim.time_s
            try:
                sim.advance(chunk)
            except Exception as exc:  # diverged: stop and say so, never show wrong numbers
                log.warning("simulation stopped: %s", exc)
                state.error = str(exc)
                state.playing = False
                break
            advanced += sim.time_s - t0
            # the new Delta31 events happened under the parameters (and ramp phase) just used
            state.d31_conditions.note(sim)  # marks where what was in force changed
            if state.ramp is not None and sim.ramp is None:
                state.stop_ramp()  # the ramp is done (the core ends it): its slider is free
        return advanced


def _timed(draw: Callable[[], None]) -> float:
    t0 = time.perf_counter()
    draw()
    return time.perf_counter() - t0

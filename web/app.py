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

import logging
import math
import threading
import time
from collections.abc import Callable

from web.drawing import Drawing
from web.pacing import RateMeter
from web.state import LoopConfig, LoopStats

log = logging.getLogger(__name__)

__all__ = ["LoopConfig", "LoopStats", "ViewerApp"]


class ViewerApp(Drawing):
    """The viewer: its lifecycle and its loop (the state, requests and drawing it inherits)."""

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
            self.d31_conditions.note(sim)  # marks where what was in force changed
            if self.ramp is not None and sim.ramp is None:
                self._stop_ramp()  # the ramp is done (the core ends it): its slider is free
        return advanced

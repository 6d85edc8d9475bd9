"""The viewer's state, shared by the loop, the requests it applies and what it draws.

See web/app.py for the threads: GUI callbacks only queue requests; the loop thread alone reads
and changes what is here.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Hashable
from dataclasses import dataclass
from pathlib import Path

import viser

from sim_core import RunSpec, Simulation
from sim_core.contract import (
    ATLAS_AXES,
    FinderOutput,
    Ramp,
    SurfaceAtlas,
    surface_atlas_file,
)
from web import controls
from web.bifurcation import WatchedFile
from web.conditions import Conditions
from web.frame_cap import SOFTWARE_FPS, install_frame_cap
from web.jobs import JobView, JobWatcher
from web.pacing import SimClock
from web.panels import Panels
from web.paths import DEFAULT_API_URL, DEFAULT_BIFURCATION, DEFAULT_SURFACE
from web.record import D31Conditions
from web.requests import (
    Request,
    RequestQueue,
)
from web.scene import HexapodScene
from web.surface_jobs import SurfaceJobs
from web.surfaces import SurfaceFiles


@dataclass(frozen=True)
class LoopConfig:
    fps: float = 30.0  # pose streaming rate; ~30 Hz is plenty for a walking insect
    # the readouts and status line, sent 8 times a second so that a page whose main thread the
    # 3D view fills (software WebGL) still shows >= 4 a second: it merges updates that arrive
    # within one of its frames (benchmarks/viewer_rtf.py at 1x: 3.2 Hz shown when sent at 5 Hz,
    # 4.7 Hz when sent at 8, stepping unchanged)
    readout_hz: float = 8.0
    panel_hz: float = 5.0  # diagrams, at most; less often when drawing them costs more
    draw_share: float = 0.15  # the loop's time the diagrams' drawing may take at most
    shadows: bool = False  # cast shadows in the 3D view (extra render passes every frame)
    software_fps: float = SOFTWARE_FPS  # the 3D view's frame cap without a GPU (frame_cap.py)
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


class ViewerState:
    """What the loop (web/app.py), its requests (web/dispatch.py) and its drawing
    (web/drawing.py) share: the simulation, the GUI, the ramp, the record's conditions and the
    loop's settings, built once here. Only the loop thread changes it after construction."""

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
        install_frame_cap(self.server, self.cfg.software_fps)
        self.panels = Panels(self.server, self.requests, self.cfg.software_fps)
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
        self.atlases: dict[tuple[str, str], WatchedFile[SurfaceAtlas]] = {
            (axis, g): WatchedFile(
                surface_atlas_file(bifurcation_path.parent, axis, g), SurfaceAtlas, "atlas"
            )
            for axis in ATLAS_AXES
            for g in controls.GROUND_LABEL
        }
        # the results folder's drift surfaces and this session's surface jobs (web/surfaces.py)
        self.surfaces = SurfaceFiles(bifurcation_path.parent, surface_path)
        self.surface_jobs = SurfaceJobs()
        self.playing = True
        self.draw_3d = True  # stream poses (SetDraw3D)
        self.speed: float | None = controls.speed_value(controls.DEFAULT_SPEED)
        self.ramp: Ramp | None = None
        self._ramp_t0 = 0.0  # when the latest ramp began (its path's export)
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

    def walk_conditions(self) -> Conditions:
        """The ground, mass and slope the walk is under now: the panels draw data of these."""
        return Conditions(self.ground, self.sim.body_mass_g, self.sim.slope_deg)

    def _on_connect(self, client: viser.ClientHandle) -> None:
        """viser's connect/disconnect hook (its thread pool): only wakes the loop."""
        self._wake.set()

    def _step(self, due: float, deadline: float) -> float:
        """Advance the walk (the loop's, web/app.py); `StepCycle` asks for one cycle."""
        raise NotImplementedError

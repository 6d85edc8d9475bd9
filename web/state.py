"""The loop's small state: the walk and how the panels show it; the loop's settings; and its
real-time bookkeeping (`SimClock`, `RateMeter`).

See web/app.py for the threads: GUI callbacks only queue requests; the loop thread alone reads
and changes a `ViewerState`, through the request handlers (web/handlers.py, which change it)
and the painters (web/painter.py, which read it). It holds no GUI: the panels, the scene and
the job links are the viewer's other parts, composed beside it in web/app.py.

The bookkeeping is pure (the caller passes the clock readings), so that "keeps real time, never
spirals when the machine is too slow, and says so" is tested without a browser or a physics
engine.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

from sim_core import RunSpec, Simulation
from sim_core.contract import ModelChoice, Ramp, RampParam, RunTemplate
from web import controls
from web.conditions import Conditions
from web.export import made_by
from web.frame_cap import SOFTWARE_FPS
from web.job_replay import Replay
from web.record import D31Conditions
from web.settings_file import JobInputs, Settings


class SimClock:
    """Simulated seconds owed to the wall clock at the chosen speed.

    If stepping cannot keep up, the debt would grow without bound and the viewer would lag
    further and further behind; instead it is capped at `max_lag_s` of wall time, so the viewer
    falls back to running as fast as it can, and the real-time factor readout shows the gap.
    """

    def __init__(self, max_lag_s: float = 0.2) -> None:
        self.max_lag_s = max_lag_s
        self.debt_s = 0.0
        self.lag_s = 0.0  # uncapped: how far behind the wall clock the walk is (the status)

    def reset(self) -> None:
        self.debt_s = 0.0
        self.lag_s = 0.0

    def tick(self, wall_dt_s: float, speed: float) -> float:
        """Add `wall_dt_s` of wall time at `speed`; returns the simulated seconds now due."""
        wall_dt_s = max(0.0, wall_dt_s)
        self.debt_s = min(self.debt_s + wall_dt_s * speed, self.max_lag_s * speed)
        self.lag_s += wall_dt_s * speed
        return self.debt_s

    def paid(self, sim_s: float) -> None:
        self.debt_s -= sim_s
        self.lag_s = max(0.0, self.lag_s - sim_s)


class RateMeter:
    """Rate of a counter over the last `window_s` of wall time (real-time factor, frame rate)."""

    def __init__(self, window_s: float = 1.0) -> None:
        self.window_s = window_s
        self._samples: deque[tuple[float, float]] = deque()

    def reset(self) -> None:
        self._samples.clear()

    def add(self, wall_s: float, total: float) -> None:
        """Record the counter's running `total` at wall time `wall_s`."""
        self._samples.append((wall_s, total))
        while len(self._samples) > 2 and wall_s - self._samples[1][0] >= self.window_s:
            self._samples.popleft()

    @property
    def rate(self) -> float | None:
        if len(self._samples) < 2:
            return None
        (w0, c0), (w1, c1) = self._samples[0], self._samples[-1]
        if w1 - w0 <= 0:
            return None
        return (c1 - c0) / (w1 - w0)


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


def _start_spec() -> RunSpec:
    """The walk the sliders start at."""
    return RunSpec(
        beta=controls.BETA.initial,
        body_mass_g=controls.BODY_MASS_G.initial,
        slope_deg=controls.SLOPE_DEG.initial,
        d31_init=controls.d31_init_value(controls.D31_INIT.initial),
    )


@dataclass(eq=False)
class ViewerState:
    """The walk (its simulation, ground, start, ramp, speed, pause, failure) and how the
    panels show it (windows, a replayed job's run); loop thread only."""

    sim: Simulation
    d31_init: float  # the initial Delta31 of the walk's last (re)start
    # the model parameters of the running simulation: ground, named setting, leaves (kept
    # across a ground switch and a loaded file; every export and job body carries them)
    model: ModelChoice = field(default_factory=ModelChoice)
    # the spec the walk started from: a new simulation (another ground or model) keeps every
    # field of it (phase_reset, the numerics, ...), the live beta, mass and slope on top
    spec: RunSpec = field(default_factory=_start_spec)
    playing: bool = True
    speed: float | None = controls.speed_value(controls.DEFAULT_SPEED)
    clock: SimClock = field(default_factory=SimClock)  # simulated time owed at `speed`
    error: str | None = None  # why the walk stopped (None: it walks)
    ramp: Ramp | None = None  # the ramp running now
    ramp_t0: float = 0.0  # when the latest ramp began (its path's export)
    last_ramp: Ramp | None = None  # the latest ramp, for its path's panel and export
    d31_conditions: D31Conditions = field(default_factory=D31Conditions)
    walk: int = 0  # bumps when the walk starts over: its record is a new one
    draw_3d: bool = True  # stream poses (SetDraw3D)
    follow: str = controls.DEFAULT_CAMERA  # the camera mode (controls.CAMERA_MODES)
    footfall_window_s: float = controls.FOOTFALL_WINDOW_S.initial
    d31_window_s: float | None = None  # None: the whole run
    replaying: Replay | None = None  # a done job's run the panels show instead of the walk's
    # values the loop sets into sliders at the next redraw (a ramp's start, a loaded file)
    write: dict[str, float] = field(default_factory=dict)
    model_words: str = ""  # `model.words()`, for the readout (set with the model)

    def __post_init__(self) -> None:
        self.model_words = self.model.words()

    @classmethod
    def of(cls, spec: RunSpec | None = None, model: ModelChoice | None = None) -> ViewerState:
        """The walk `spec` (None: the sliders' initial values) with `model`'s parameters
        (None: the defaults, on the default ground)."""
        spec, model = spec or _start_spec(), model or ModelChoice()
        return cls(Simulation(spec, model.model_params()), spec.d31_init, model, spec)

    @property
    def ground(self) -> str:
        """`ModelParams.ground` of the running simulation."""
        return self.model.ground

    def conditions(self) -> Conditions:
        """The ground, mass and slope the walk is under now: the panels draw data of these."""
        return Conditions(self.ground, self.sim.body_mass_g, self.sim.slope_deg)

    def set(self, name: RampParam, value: float) -> None:
        """A live parameter, clamped to its slider's range (a ramp's own is left to it)."""
        self.sim.set(name, controls.RAMP_SLIDERS[name].clamp(value))

    def start_ramp(self, ramp: Ramp) -> None:
        """Ramp `ramp.param` by the core's ramp driver from now on (a running one ends)."""
        self.stop_ramp()
        self.ramp, self.last_ramp, self.ramp_t0 = ramp, ramp, self.sim.time_s
        self.sim.start_ramp(ramp)  # the core's ramp driver moves the parameter
        self.write[ramp.param] = ramp.start  # the slider shows the start, once
        self.d31_conditions.start_ramp(self.sim)  # a new ramp draws a new path

    def stop_ramp(self) -> None:
        """End the ramp where it is; its slider then shows the value the ramp left."""
        if self.ramp is not None:
            self.write[self.ramp.param] = self.sim.get(self.ramp.param)
        self.ramp = None
        self.sim.stop_ramp()

    def restart(
        self, d31_init: float, ground: str | None = None, model: ModelChoice | None = None,
        run: RunTemplate | None = None,
    ) -> None:  # fmt: skip
        """A new walk from `d31_init` at the parameters in force, on `ground` (None: the
        same one) with `model`'s parameters (None: the ones in force, which another ground
        keeps: a leaf the other ground lacks is refused, naming it) and `run`'s fields (a
        loaded file's; None: the walk's); others build a new simulation; the record restarts."""
        want = model or self.model
        if ground is not None and ground != want.ground:  # the other leaves kept, checked
            want = ModelChoice.read(want.model_dump() | {"ground": ground})
        self.stop_ramp()
        self.d31_init = controls.d31_init_value(d31_init)
        now = self.now()
        if run is not None:  # the file's fields; the walk's per-run ones (beta, the start)
            now = run.spec(**{n: v for n, v in now if n not in RunTemplate.model_fields})
        if want == self.model and now == self.now():
            self.sim.reset(d31_init=self.d31_init)
        else:
            self.sim = Simulation(now, want.model_params())
            self.spec, self.model, self.model_words = now, want, want.words()
        self.d31_conditions.clear()
        self.walk += 1
        self.clock.reset()
        self.error = None
        self.playing = True

    def now(self) -> RunSpec:
        """The walk's spec now: the one it started from, the live parameters in force on top."""
        live = {name: self.sim.get(name) for name in controls.LIVE_NAMES}
        return self.spec.model_copy(update=live | {"d31_init": self.d31_init})

    def settings(self, inputs: JobInputs) -> Settings:
        """The walk's settings as the export and the job bodies say them: its whole spec (the
        core's run template, the beta now and the last start) and its model parameters."""
        running, now = self.ramp is not None, self.now()
        return Settings(
            run=RunTemplate.of(now),
            beta=now.beta,
            d31_init=now.d31_init,
            speed=self.speed,
            time_s=self.sim.time_s,
            model=self.model,
            ramp=self.ramp if running else inputs.ramp,  # the one running, else the one set up
            ramp_running=running,
            ramp_started_at_s=self.ramp_t0 if running else None,
            job_duration_s=inputs.duration_s,
            api_url=inputs.api_url,
        )

    def provenance(self) -> dict[str, object]:
        """What makes the walk's numbers, for every export (`export.made_by`)."""
        return made_by(self.model)

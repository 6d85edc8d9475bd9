"""A live, steppable simulation: the viewer's engine, and a notebook's.

It is a batch of one (`BatchRunner`), so what it shows is what `simulate` computes; beta, body
mass and slope change between control periods without a restart. Its history is the runner's
own record in ring mode (`records.Recorder`: stance and body pose every control period, the
last `history_s` seconds), so that it can run forever; the Delta31 events grow with the run.
Not thread-safe: one thread owns it.
"""

from __future__ import annotations

from typing import NamedTuple

import mujoco
import numpy as np

from sim_core.model import gait
from sim_core.model.mjspec import build_model
from sim_core.model.params import ModelParams
from sim_core.model.ramp import (
    RAMP_PARAMS,
    EventConditions,
    Ramp,
    RampDriver,
    RampParam,
    set_ramped,
)
from sim_core.model.runner import BatchRunner
from sim_core.model.spec import RunFailure, RunSpec, SimulationDiverged


class _Window(NamedTuple):
    """What `Simulation` reads off its record's last second, keyed by the rows recorded."""

    rows: int
    stance: np.ndarray
    speed_m_s: float | None
    heading_rad: float | None


class Simulation:
    """One hexapod walking in real time; see docs/CORE_API.md for the contract."""

    def __init__(
        self,
        spec: RunSpec | None = None,
        params: ModelParams | None = None,
        history_s: float = 20.0,
    ) -> None:
        self._spec = spec or RunSpec()
        self._params = params
        self._history_s = history_s
        self._build()

    def _build(self) -> None:
        self._runner = BatchRunner([self._spec], self._params, nthread=1, record_dt=0.0,
                                   open_ended=True, history_s=self._history_s)  # fmt: skip
        assert self._runner.recorder is not None
        self._record = self._runner.recorder
        # drawing needs the visual geoms the physics leaves out; same bodies and joints
        self._render_model = build_model(self._runner.params, visual=True)
        self._data = mujoco.MjData(self._render_model)
        self._events: list[tuple[float, float]] = []  # grows with the run; never rebuilt
        self._conditions: list[EventConditions] = []  # in force at each event, index for index
        self._window: _Window | None = None
        self._ramp: Ramp | None = None
        self._driver: RampDriver | None = None  # drives `_ramp` from its start (`t0`)
        self._phase = ""  # the ramp's phase in force for the coming control period

    # --- controls -----------------------------------------------------------------------------
    def advance(self, sim_seconds: float) -> None:
        """Simulate `sim_seconds` more, in whole control periods (at least one)."""
        r = self._runner
        if r.failures[0] is None:
            nblocks = max(1, round(sim_seconds / r.control_dt))
            r.run(hook=self._after_period, max_blocks=nblocks)
        if r.failures[0] is not None:
            raise SimulationDiverged(r.failures[0])

    def set(self, param: RampParam, value: float) -> None:
        """Set live parameter `param` to `value` (beta, g or degrees; checked against RunSpec's
        range) from the next control period on: one typed call for every live parameter, so a
        caller (the viewer) names it by the same Literal a `Ramp` does, never by a method name
        built from a string."""
        r = self._runner
        match param:
            case "beta":
                r.set_beta(0, value)
            case "body_mass_g":
                r.set_body_mass_g(0, value)
            case "slope_deg":
                r.set_slope_deg(0, value)
            case _:
                raise ValueError(f"no live parameter {param!r}; choose from {list(RAMP_PARAMS)}")

    def get(self, param: RampParam) -> float:
        """The value of live parameter `param` in force now (what `set` set, or a ramp)."""
        match param:
            case "beta":
                return self.beta
            case "body_mass_g":
                return self.body_mass_g
            case "slope_deg":
                return self.slope_deg
            case _:
                raise ValueError(f"no live parameter {param!r}; choose from {list(RAMP_PARAMS)}")

    def set_beta(self, beta: float) -> None:
        self.set("beta", beta)

    def set_body_mass_g(self, mass_g: float) -> None:
        self.set("body_mass_g", mass_g)

    def set_slope_deg(self, slope_deg: float) -> None:
        self.set("slope_deg", slope_deg)

    def start_ramp(self, ramp: Ramp) -> None:
        """Ramp `ramp.param` from now on (hold, to the turn, back, hold) by the core's one
        ramp driver, as the reproduction's ramps are driven; a running ramp is replaced. When
        it is done the parameter stays at its start value and the ramp ends."""
        self._ramp = ramp
        self._driver = RampDriver(
            [(0, ramp)], self.control_dt_s, t0=self.time_s, start_block=self._runner.nblock
        )
        self._driver(self._runner)  # the value of the coming period
        self._phase = ramp.phase(0.0)

    def stop_ramp(self) -> None:
        """End the ramp where it is: the parameter keeps the value the ramp left."""
        self._ramp, self._driver, self._phase = None, None, ""

    @property
    def ramp(self) -> Ramp | None:
        """The ramp running now (None: none)."""
        return self._ramp

    @property
    def ramp_started_at_s(self) -> float | None:
        return self._driver.t0 if self._driver is not None else None

    @property
    def ramp_phase(self) -> str:
        """The running ramp's phase ("hold", "down", "up"), "" without one."""
        return self._phase

    def reset(self, d31_init: float | None = None) -> None:
        """Start over with a new initial Delta31; beta, mass and slope are kept (a running
        ramp ends)."""
        keep = {"beta": self.beta, "body_mass_g": self.body_mass_g, "slope_deg": self.slope_deg}
        if d31_init is not None:
            keep["d31_init"] = d31_init
        self._spec = self._spec.model_copy(update=keep)
        self._build()

    # --- state --------------------------------------------------------------------------------
    @property
    def error(self) -> str | None:
        failure = self._runner.failures[0]
        return None if failure is None else str(failure)

    @property
    def failure(self) -> RunFailure | None:
        return self._runner.failures[0]

    @property
    def time_s(self) -> float:
        return self._runner.time

    @property
    def beta(self) -> float:
        return float(self._runner.beta[0])

    @property
    def body_mass_g(self) -> float:
        return float(self._runner.body_mass_g[0])

    @property
    def slope_deg(self) -> float:
        return float(self._runner.slope_deg[0])

    @property
    def control_dt_s(self) -> float:
        return self._runner.control_dt

    @property
    def model(self) -> mujoco.MjModel:
        """The hexapod with its visual geoms, for drawing (the physics runs without them)."""
        return self._render_model

    @property
    def data(self) -> mujoco.MjData:
        """A snapshot of the current state with body/geom poses of `model` computed, for
        rendering."""
        r = self._runner
        self._data.qpos[:] = r.qpos[0]  # same bodies and joints: the physics state is ours
        self._data.qvel[:] = r.qvel[0]
        self._data.time = r.time
        mujoco.mj_kinematics(self._render_model, self._data)
        return self._data

    @property
    def stance(self) -> np.ndarray:
        return self._runner.legs.stance[0] != 0

    @property
    def phases(self) -> np.ndarray:
        return self._runner.legs.phi[0].copy()

    @property
    def d31_now(self) -> float:
        p = self._runner.legs.phi[0]
        return float(gait.wrap(p[2] - p[0]))

    @property
    def d31_events(self) -> list[tuple[float, float]]:
        """(time, Delta31) at each leg-1 touchdown since the last reset; extended in place, so a
        caller may keep an index into it and read only what is new."""
        return self._events

    @property
    def footfall(self) -> tuple[np.ndarray, np.ndarray]:
        """(times (T,), stance (T, 6) bool) over the kept history."""
        return self.footfall_since(None)

    def footfall_since(self, after_s: float | None) -> tuple[np.ndarray, np.ndarray]:
        """(times (T,), stance (T, 6) bool) of the kept history later than `after_s` (all of it
        for None): what a caller keeping its own rolling window has not seen yet, at every
        control period (the viewer's footfall diagram). Copies."""
        s = self._record.since(0, after_s)
        return np.array(s.times_s), np.array(s.stance, dtype=bool).reshape(-1, 6)

    def stance_intervals(self) -> list[list[tuple[float, float]]]:
        """Per leg, (start, end) of every stance since the last reset (s), from the touchdown
        and lift-off events (kept for the whole run, where `footfall` keeps `history_s`); a
        leg standing from the start counts from 0, one standing now ends now."""
        ev = self._runner.journal
        tds = [([0.0] if lo and (not td or lo[0] < td[0]) else []) + td
               for td, lo in zip(ev.touchdowns[0], ev.liftoffs[0], strict=True)]  # fmt: skip
        return gait.stance_intervals(tds, ev.liftoffs[0], 0.0, self.time_s)

    def _last_second(self) -> _Window:
        """The record's last second and the heading speed over it, computed once per recorded
        row (the viewer reads speed, heading and duty factor every frame)."""
        if self._window is None or self._window.rows != self._record.n_rows:
            s = self._record.since(0, self.time_s - 1.0)
            speed, heading = gait.heading_speed(s.times_s, s.body_pos_m, s.body_quat)
            self._window = _Window(self._record.n_rows, s.stance, speed, heading)
        return self._window

    @property
    def speed_cm_s(self) -> float | None:
        """Speed along the body's heading over the last second (`gait.heading_speed`), cm/s."""
        v = self._last_second().speed_m_s
        return None if v is None else 100.0 * v

    @property
    def heading_rad(self) -> float | None:
        """The body's mean heading over the last second (rad from world +x towards +y)."""
        return self._last_second().heading_rad

    @property
    def duty_factor(self) -> float | None:
        """All legs' stance fraction over the last second (`gait.duty_factor` of that window)."""
        return gait.duty_factor(self._last_second().stance, fraction=1.0)

    @property
    def gait(self) -> str:
        """The gait walked now (`gait.live_gait`): the footfall of the last three cycles, or
        "changing" while Delta31 drifts faster than the settled rule; a live label, not a
        claim that the run has settled."""
        r, ev, n = self._runner, self._runner.journal, gait.LIVE_LAST
        # each leg's last n events cover the three cycles read (the lists grow with the run)
        return gait.live_gait(r.d31_v[0][-n:], r.d31_t[0][-n:],
                              [t[-n:] for t in ev.touchdowns[0]], [t[-n:] for t in ev.liftoffs[0]],
                              self.time_s, self.beta)  # fmt: skip

    @property
    def d31_conditions(self) -> list[EventConditions]:
        """What was in force at each Delta31 event (index for index with `d31_events`): the
        parameters, the ground and the ramp's phase; extended in place, as the events."""
        return self._conditions

    def _after_period(self, r: BatchRunner) -> None:
        """The run loop's hook after every control period: the new Delta31 events with what
        was in force during the period, then the ramp's value for the next one."""
        t, v = r.d31_t[0], r.d31_v[0]
        if len(v) > len(self._events):
            ramp = self._ramp
            now = EventConditions(
                float(r.beta[0]), float(r.body_mass_g[0]), float(r.slope_deg[0]),
                r.params.contact.ground, self._phase, ramp.param if ramp is not None else "",
            )  # fmt: skip
            for k in range(len(self._events), len(v)):
                self._events.append((t[k], v[k]))
                self._conditions.append(now)
        ramp, driver = self._ramp, self._driver
        if ramp is not None and driver is not None:
            phase = ramp.phase(r.time - driver.t0)
            if phase == "done":
                set_ramped(r, 0, ramp.param, ramp.start)
                self.stop_ramp()
            else:
                driver(r)
                self._phase = phase

"""Run one or many simulations: MuJoCo's `Batch` for the physics, the compiled controller between.

A single simulation is a batch of one, so that `simulate` and `simulate_batch` share every line
and give bit-identical results (`mujoco.batch` is bit-identical to one MjData per simulation at
any thread count, and the controller treats each simulation independently).

Every control period the runner checks each simulation: finite state, body above the floor,
not flipped, no MuJoCo warning. A simulation that fails stops there and keeps a `RunFailure`
(kind, time, integrator, timestep, reason); it returns no numbers.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from typing import Any, cast

import mujoco
import mujoco.batch
import numba
import numpy as np

from sim_core.model.anatomy import attachment_points, leg_reach
from sim_core.model.controller import (
    Drive,
    EventLog,
    LegState,
    TouchRules,
    apply_events,
    initial_targets,
    plan_block,
)
from sim_core.model.cost import RECORD_DT_S
from sim_core.model.cpg import initial_phases
from sim_core.model.gait import settling
from sim_core.model.guard import (
    FLIPPED,
    LEFT_GROUND,
    NO_FOOTHOLDS,
    NON_FINITE,
    ON_FLOOR,
    SLIDING_BACK,
    WARNED,
    Limits,
    guard_codes,
    new_footing,
    up_axis_z,
)
from sim_core.model.legs import leg_geometry
from sim_core.model.mjspec import build_model, gravity_vector, leg_qpos_addresses, servo_leads
from sim_core.model.params import ModelParams, nominal_speed, omega, phi_aep
from sim_core.model.records import NOT_RECORDED, EventJournal, Recorder, assemble_result
from sim_core.model.spec import (
    NO_FOOTHOLD_S,
    SLIDE_BACK_SPEED_M_S,
    SLIDE_WINDOW_S,
    FailureKind,
    RunFailure,
    RunResult,
    RunSpec,
    check_field,
    cost_problem,
    resolve_numerics,
)

TORSO = 1  # body id of the torso (world is 0)
# Guard: the body box touching the floor, or tilted past 60 degrees, is a fall, not walking.
MIN_UP_COS = 0.5

ProgressFn = Callable[[float], None]
BlockHook = Callable[["BatchRunner"], None]
# What a runner compiles its model with (params, visual=False): `mjspec.build_model`, or a
# study's variant of it passed as `build` (a seam, so that no study patches this module).
ModelBuilder = Callable[..., mujoco.MjModel]


def spec_numerics(spec: RunSpec, params: ModelParams) -> tuple[str, float, float, int]:
    """(integrator, dt, control_dt, substeps per control period) for a spec."""
    return resolve_numerics(spec.integrator, spec.dt_s, spec.control_dt_s, params)


def bind_kernel(kernel: Any, args: tuple[Any, ...]) -> Callable[..., Any]:
    """The compiled overload of a numba kernel for these arguments' types, called directly.

    numba types every argument on every call; for a NamedTuple of arrays that costs ~1 us plus
    ~0.13 us per field (measured), about 4% of one simulation's time at six grouped arguments
    per control period. The runner's arrays keep their types for its whole life (made once in
    __init__, slices of fixed layout), so the overload is looked up once.
    """
    sig = tuple(numba.typeof(a) for a in args)
    kernel.compile(sig)
    return cast(Callable[..., Any], kernel.overloads[sig].entry_point)


class BatchRunner:
    """n simulations of one model stepped together; the engine under every public entry point.

    All simulations share the integrator, timestep and control period (a batch steps them in
    lock-step); beta, body mass, slope and the phase-reset switch are per simulation and may
    change between control periods (`set_beta`, `set_body_mass_g`, `set_slope_deg`).

    Each simulation runs for its spec's `duration_s`, or without end when `open_ended` (the
    live `Simulation`, which steps on demand and keeps only its last `history_s` seconds, a
    ring record, every `record_dt`: 0 records every control period).
    """

    def __init__(
        self,
        specs: Sequence[RunSpec],
        params: ModelParams | None = None,
        nthread: int = 0,
        record_dt: float = RECORD_DT_S,
        record: bool = True,
        open_ended: bool = False,
        history_s: float | None = None,
        build: ModelBuilder = build_model,
    ) -> None:
        if not specs:
            raise ValueError("no simulations to run")
        if open_ended and record and history_s is None:
            raise ValueError("an open-ended batch records only a bounded history (history_s)")
        base = params or ModelParams()
        for s in specs:  # validate before allocating: a 1e-12 s step once asked for 67 GiB
            problem = cost_problem(s.duration_s, s.integrator, s.dt_s, s.control_dt_s)
            if problem:
                raise ValueError(problem)
        numerics = {spec_numerics(s, base) for s in specs}
        if len(numerics) != 1:
            raise ValueError("one BatchRunner needs one (integrator, dt, control_dt); group specs")
        self.integrator, self.dt, self.control_dt, self.nsub = numerics.pop()
        self.params = base.replace(**{"integrator": self.integrator, "dt": self.dt})
        self.specs = list(specs)
        n = self.n = len(specs)
        self.model = build(self.params, visual=False)  # drawing: Simulation.model
        self._leg_qpos = leg_qpos_addresses(self.model)  # fixed by the model; used per reset
        self.batch = mujoco.batch.Batch(self.model, nsim=n, nthread=nthread if n > 1 else 1)
        self.geo = leg_geometry(self.params)
        self._lead = servo_leads(self.params)
        p = self.params
        self._torso_inertia = self.model.body_inertia[TORSO].copy()

        self.beta = np.zeros(n)
        # the controller's state, what beta drives (eq. 2) and the last period's events: each
        # array under one name, in the NamedTuples the compiled kernels take
        self.drive = Drive(omega=np.zeros(n), phi_aep=np.zeros(n), reset=np.ones(n, np.bool_),
                           pin_d31=np.zeros(n), pin_gain=np.zeros(n))  # fmt: skip
        self.legs = LegState(
            phi=np.zeros((n, 6)),
            phi_next=np.zeros((n, 6)),
            stance=np.zeros((n, 6), dtype=np.int8),
            lp=np.zeros((n, 6, 3)),
            phi_td=np.zeros((n, 6)),
            prev_height=np.zeros((n, 6)),
            lifted=np.zeros((n, 6), dtype=np.bool_),
            retouches=np.zeros(n, dtype=np.int64),  # stance feet that left and came back
        )
        self.log = EventLog(
            td_time=np.full((n, 6), np.nan),
            td_phase=np.full((n, 6), np.nan),
            lo_time=np.full((n, 6), np.nan),
            d31=np.full(n, np.nan),
        )
        self.body_mass_g = np.full(n, p.body.body_mass * 1e3)
        self.slope_deg = np.zeros(n)
        self.duration = (
            np.full(n, np.inf) if open_ended else np.array([s.duration_s for s in specs])
        )
        self._first_end = float(self.duration.min()) - 1e-12  # no run ends before this time
        # RunSpec.stop_if_settled_s: when each run's settled test is due (inf: never), and the
        # earliest one still due (one float compared per control period)
        self._settle_due = np.array(
            [np.inf if s.stop_if_settled_s is None else s.stop_if_settled_s for s in specs]
        )
        self._next_settle_due = float(self._settle_due.min()) - 1e-12
        self.feet = np.zeros((n, self.nsub, self.model.nsite, 3))
        self._warn_seen = np.zeros(self.batch.warning.shape[:2], dtype=np.int64)
        self._guard_codes = np.zeros(n, dtype=np.int64)
        self._guard_values = np.zeros(n)
        self._attach = attachment_points(p)
        self._limits = Limits(p.body.body_thickness / 2, MIN_UP_COS, leg_reach(p), NO_FOOTHOLD_S,
                              SLIDE_WINDOW_S, SLIDE_BACK_SPEED_M_S)  # fmt: skip
        self._footing = new_footing(n)
        self._guard_kernel: Callable[..., int] | None = None
        self.qpos = self.batch.bind("qpos")
        self.act = self.batch.bind("act")  # the PD set-points (integrator dynamics)
        self.ctrl = self.batch.bind("ctrl")  # desired joint velocities
        self.qvel = self.batch.bind("qvel")
        touch = p.oscillators
        self._rules = TouchRules(p.legs.foot_radius, touch.touch_depth, touch.scuff_fraction,
                                 p.numerics.touchdown_interpolation,
                                 touch.lift_clearance)  # fmt: skip
        self._plan: Callable[..., None] | None = None  # the kernels, bound at the first period
        self._events: Callable[..., int] | None = None
        self.nblock = 0
        # wall seconds spent in each part of step_block, for `insect-gait bench`
        self.timers = {"controller": 0.0, "physics": 0.0, "bookkeeping": 0.0}
        self.active = np.ones(n, dtype=np.bool_)
        self.failures: list[RunFailure | None] = [None] * n
        # what happened (events) and what was sampled (time series): kept beside the stepping
        self.journal = EventJournal(n, p.trajectory.stroke)
        self.recorder: Recorder | None = None
        if record:
            every = max(1, round(record_dt / self.control_dt))
            if history_s is not None:  # the last history_s seconds only, as a ring
                nrec = math.ceil(history_s / (every * self.control_dt)) + 1
                self.recorder = Recorder(n, nrec, every, ring=True)
            else:
                nrec = math.ceil(self.duration.max() / (every * self.control_dt)) + 2
                self.recorder = Recorder(n, nrec, every)

        self.batch.reset()
        for i, spec in enumerate(specs):
            self.set_beta(i, spec.beta)
            self.drive.reset[i] = spec.phase_reset
            if spec.pin_d31 is not None:  # the drift surface's instrument (cpg.pin)
                self.drive.pin_d31[i] = spec.pin_d31
                self.drive.pin_gain[i] = spec.pin_gain_per_s
            if spec.body_mass_g != p.body.body_mass * 1e3:
                self.set_body_mass_g(i, spec.body_mass_g)
            if spec.slope_deg != 0.0:
                self.set_slope_deg(i, spec.slope_deg)
            self.init_state(i, spec.d31_init, spec.phi1_init)
        self._record(np.arange(n))

    @property
    def d31_t(self) -> list[list[float]]:
        """Per simulation, the times (s) of its leg-1 touchdowns so far."""
        return self.journal.d31_t

    @property
    def d31_v(self) -> list[list[float]]:
        """Per simulation, Delta31 (rad) at each of its leg-1 touchdowns so far."""
        return self.journal.d31_v

    # --- per-simulation settings, live ---------------------------------------------------
    @property
    def time(self) -> float:
        return self.nblock * self.control_dt

    def set_beta(self, i: int, beta: float) -> None:
        check_field("beta", beta)
        self.beta[i] = beta
        self.drive.omega[i] = omega(beta, self.params.trajectory.swing_duration)
        self.drive.phi_aep[i] = phi_aep(beta)

    def set_body_mass_g(self, i: int, mass_g: float) -> None:
        check_field("body_mass_g", mass_g)
        mass = self.batch.expand("body_mass")
        inertia = self.batch.expand("body_inertia")
        mass[i, TORSO] = mass_g * 1e-3
        inertia[i, TORSO] = self._torso_inertia * (mass_g * 1e-3 / self.params.body.body_mass)
        self.body_mass_g[i] = mass_g
        self.batch.set_const(np.array([i]))

    def set_slope_deg(self, i: int, slope_deg: float) -> None:
        check_field("slope_deg", slope_deg)
        self.batch.expand("opt.gravity")[i] = gravity_vector(slope_deg)
        self.slope_deg[i] = slope_deg

    def init_state(self, i: int, d31: float, phi1: float = 0.0) -> None:
        """Put simulation i at rest-ish on its feet with the gait family member d31."""
        p = self.params
        self.legs.phi[i] = initial_phases(d31, phi1)
        self.legs.stance[i] = (self.legs.phi[i] >= self.drive.phi_aep[i]).astype(np.int8)
        aep = self.geo.aep
        self.legs.lp[i] = aep
        self.legs.phi_td[i] = self.drive.phi_aep[i]
        q = np.zeros(18)
        tips = np.zeros((6, 3))
        initial_targets(
            self.legs.phi[i],
            self.legs.stance[i],
            self.legs.lp[i],
            self.legs.phi_td[i],
            self.drive.phi_aep[i],
            self.geo,
            q,
            tips,
        )
        qpos = np.zeros(self.model.nq)
        qpos[2] = p.trajectory.stand_height - p.legs.attach_z + p.legs.foot_radius
        qpos[3] = 1.0
        qpos[self._leg_qpos] = q
        self.qpos[i] = qpos
        qvel = np.zeros(self.model.nv)
        qvel[0] = nominal_speed(self.beta[i], p.trajectory.stroke, p.trajectory.swing_duration)
        self.qvel[i] = qvel
        self.active[i] = True
        self.failures[i] = None
        self.legs.lifted[i] = False
        self.legs.retouches[i] = 0
        self._footing.x_ref[i] = qpos[0]
        self._footing.t_ref[i] = self.time
        self._footing.t_foothold[i] = self.time

    # --- stepping ---------------------------------------------------------------------------
    def step_block(self) -> None:
        """Advance every active simulation by one control period (`run` is the loop)."""
        ids = np.flatnonzero(self.active)
        m = ids.size
        if m == 0:
            return
        p = self.params
        clock = time.perf_counter
        t_start = clock()
        k = p.oscillators
        plan_args = (ids, self.legs, self.drive, k.k_contralateral, k.k_ipsilateral,
                     self.control_dt, self.geo, self._lead, self.act, self.ctrl,
                     self.qpos)  # fmt: skip
        if self._plan is None:
            self._plan = bind_kernel(plan_block, plan_args)
        self._plan(*plan_args)
        call_ids = None if m == self.n else ids
        t_plan = clock()
        try:
            self.batch.rollout(
                self.nsub,
                record=("site_xpos",),
                ids=call_ids,
                out={"site_xpos": self.feet[:m]},
            )
        except mujoco.batch.SimulationError as exc:
            for sim in exc.ids:
                self._fail(int(sim), "mujoco_error", f"MuJoCo error: {self.batch.error(int(sim))}")
        t_phys = clock()
        t0 = self.time
        event_args = (ids, self.feet[:m, :, :, 2], t0, self.dt, self.legs, self.drive,
                      self._rules, self.geo, self.log)  # fmt: skip
        if self._events is None:
            self._events = bind_kernel(apply_events, event_args)
        events = self._events(*event_args)
        self.nblock += 1
        if events:
            log = self.log
            self.journal.collect(ids, log.td_time[ids], log.td_phase, log.lo_time[ids], log.d31,
                                 self.feet[:m, -1, :, :2])  # fmt: skip
        t_ctrl = clock()
        if self.recorder is not None and self.nblock % self.recorder.every == 0:
            self._record(ids)
        self._guard(ids)
        tm = self.timers
        tm["controller"] += (t_plan - t_start) + (t_ctrl - t_phys)
        tm["physics"] += t_phys - t_plan
        tm["bookkeeping"] += clock() - t_ctrl

    def _guard(self, ids: np.ndarray) -> None:
        codes = self._guard_codes[: ids.size]
        values = self._guard_values[: ids.size]
        args = (ids, self.qpos, self.qvel, self.batch.warning, self._warn_seen, self.legs.stance,
                self.time, self._attach, self._limits, self._footing, codes, values)  # fmt: skip
        if self._guard_kernel is None:
            self._guard_kernel = bind_kernel(guard_codes, args)
        failed = self._guard_kernel(*args)
        if self.time >= self._first_end:
            done = self.time >= self.duration[ids] - 1e-12
            self.active[ids[done]] = False
        if not failed:
            return
        for r in np.flatnonzero(codes):
            s = int(ids[r])
            if self.failures[s] is not None:
                continue
            code = codes[r]
            if code == WARNED:
                kinds = self.batch.warning[s, :, 1] > 0
                names = [mujoco.mjtWarning(k).name for k in np.flatnonzero(kinds)]
                why = "MuJoCo warning " + ", ".join(names) + " (unstable: state was reset)"
                kind: FailureKind = "mujoco_warning"
            elif code == NON_FINITE:
                why, kind = "non-finite state", "non_finite"
            elif code == FLIPPED:
                up_z = up_axis_z(self.qpos[s, 3:7])
                why, kind = f"body flipped (up-axis z {up_z:.2f} < {MIN_UP_COS})", "flipped"
            elif code == ON_FLOOR:
                why = f"body on the floor (height {self.qpos[s, 2] * 1e3:.2f} mm)"
                kind = "on_floor"
            else:
                why, kind = self._physics_failure(int(code), float(values[r]))
            self._fail(s, kind, why)

    def _physics_failure(self, code: int, value: float) -> tuple[str, FailureKind]:
        """The words and kind of a failed physical-sanity check (`guard`, thresholds in spec)."""
        lim = self._limits
        if code == LEFT_GROUND:
            return (
                f"body left the ground (lowest coxa attachment {value * 1e3:.1f} mm above the "
                f"floor, beyond the legs' {lim.reach * 1e3:.2f} mm reach)",
                "left_ground",
            )
        if code == NO_FOOTHOLDS:
            return f"no leg had a foothold for {value:.3g} s (every leg in swing)", "no_footholds"
        assert code == SLIDING_BACK, code
        return (
            f"body slid backwards at {value * 100:.1f} cm/s over the last "
            f"{lim.slide_window_s:g} s (walking runs stay above "
            f"-{lim.slide_speed * 100:g} cm/s)",
            "sliding_back",
        )

    def _fail(self, s: int, kind: FailureKind, why: str) -> None:
        self.failures[s] = RunFailure(kind, self.time, self.integrator, self.dt, why)
        self.active[s] = False

    def _record(self, live: np.ndarray) -> None:
        if self.recorder is not None:
            self.recorder.take(self.time, live, self.legs.stance, self.qpos, self.qvel)

    def run(
        self,
        progress: ProgressFn | None = None,
        *,
        hook: BlockHook | None = None,
        max_blocks: int | None = None,
    ) -> None:
        """Step until every simulation reached its duration or failed, or for `max_blocks`
        control periods: the one run loop under `simulate`, `simulate_batch`, the
        reproduction's tasks (ramps), `Simulation` (the viewer) and the benchmarks.

        Args:
            progress: called with the share of the simulated time done (0..1), about every
                1% and at the end (finite durations only).
            hook: called as hook(self) after every control period: the place to read state
                (a live history) or to set a value for the next period (a ramp).
            max_blocks: stop after this many control periods (a live simulation's advance).
        """
        total = float(self.duration.sum())
        report = progress is not None and math.isfinite(total) and total > 0
        last = -1.0
        done_blocks = 0
        while self.active.any() and (max_blocks is None or done_blocks < max_blocks):
            self.step_block()
            done_blocks += 1
            if self.time >= self._next_settle_due:
                self._stop_settled()
            if hook is not None:
                hook(self)
            if report:
                done = float(np.minimum(self.time, self.duration).sum()) / total
                if done - last >= 0.01 or not self.active.any():
                    progress(done)  # type: ignore[misc]
                    last = done

    def _stop_settled(self) -> None:
        """Runs whose `stop_if_settled_s` has come: those that settled end now, exactly as a
        run of this length would have (the same control period ends both)."""
        due = np.flatnonzero(self._settle_due <= self.time + 1e-12)
        for i in due:
            if self.active[i] and settling(self.journal.d31_v[i]).settled:
                self.end(int(i))
        self._settle_due[due] = np.inf
        self._next_settle_due = float(self._settle_due.min()) - 1e-12

    def end(self, i: int) -> None:
        """End simulation i now: its duration becomes the time reached (its result is that of
        a run this long)."""
        self.duration[i] = self.time
        self.active[i] = False

    # --- results ----------------------------------------------------------------------------
    def result(self, i: int) -> RunResult:
        ev = self.journal
        ser = NOT_RECORDED if self.recorder is None else self.recorder.series(i)
        return assemble_result(
            spec=self.specs[i], integrator=self.integrator, dt_s=self.dt,
            control_dt_s=self.control_dt, failure=self.failures[i], d31=ev.d31_v[i],
            d31_times_s=ev.d31_t[i], series=ser,
            touchdowns=ev.touchdowns[i], touchdown_phases=ev.touchdown_phases[i],
            liftoffs=ev.liftoffs[i], slips=ev.slips[i], retouches=int(self.legs.retouches[i]),
            phi_aep=float(self.drive.phi_aep[i]), duration_s=float(self.duration[i]),
        )  # fmt: skip


def simulate(spec: RunSpec, params: ModelParams | None = None) -> RunResult:
    """Run one simulation (a batch of one: the same code and numbers as `simulate_batch`)."""
    runner = BatchRunner([spec], params, nthread=1)
    runner.run()
    return runner.result(0)


def simulate_batch(
    specs: Sequence[RunSpec],
    params: ModelParams | None = None,
    *,
    nthread: int = 0,
    progress: ProgressFn | bool | None = None,
) -> list[RunResult]:
    """Run many simulations on a thread pool; results in the order of `specs`.

    Specs with different numerics (integrator, dt, control period) run as separate batches.
    nthread = 0 uses every core. progress: a function called with the share of the simulated
    time done (0..1), or True for a tqdm bar in simulated seconds (a notebook shows its own).
    """
    if progress is True:
        from tqdm.auto import tqdm

        total_s = float(sum(s.duration_s for s in specs))
        with tqdm(total=round(total_s, 3), unit="sim s", desc="simulate_batch") as bar:

            def advance(frac: float) -> None:
                bar.update(round(frac * total_s, 3) - bar.n)

            done = simulate_batch(specs, params, nthread=nthread, progress=advance)
            advance(1.0)
            return done
    if progress is False:
        progress = None
    base = params or ModelParams()
    groups: dict[tuple[str, float, float, int], list[int]] = {}
    for i, s in enumerate(specs):
        groups.setdefault(spec_numerics(s, base), []).append(i)
    out: list[RunResult | None] = [None] * len(specs)
    total = float(sum(s.duration_s for s in specs))
    done_before = 0.0
    for idx in groups.values():
        group_time = float(sum(specs[i].duration_s for i in idx))
        runner = BatchRunner([specs[i] for i in idx], base, nthread=nthread)
        if progress is not None:
            prev = done_before

            def report(frac: float, prev: float = prev, gt: float = group_time) -> None:
                progress((prev + frac * gt) / total)

            runner.run(report)
        else:
            runner.run()
        for k, i in enumerate(idx):
            out[i] = runner.result(k)
        done_before += group_time
    return [r for r in out if r is not None]

"""A finished run's raw records -> `RunResult`: the gait measures computed once, here.

The runner keeps what happened (touchdowns, lift-offs, Delta31 at leg-1 touchdowns, the
recorded body state); what they mean (where the run ended, speed, duty factor, slip, landing
share, contact chatter) is computed by `model.gait` when a result is asked for.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from sim_core.model import gait
from sim_core.model.params import ModelParams
from sim_core.model.spec import (
    RunEvents,
    RunFailure,
    RunMeasures,
    RunResult,
    RunSeries,
    RunSpec,
)

# the step docs/NUMERICS.md measured converged; a run on a coarser one says so in its warnings
CONVERGED_DT_S = ModelParams().numerics.dt


def assemble_result(
    *,
    spec: RunSpec,
    integrator: str,
    dt_s: float,
    control_dt_s: float,
    failure: RunFailure | None,
    d31: Sequence[float],
    d31_times_s: Sequence[float],
    series: RunSeries,
    touchdowns: Sequence[Sequence[float]],
    touchdown_phases: Sequence[Sequence[float]],
    liftoffs: Sequence[Sequence[float]],
    slips: Sequence[float],
    retouches: int,
    phi_aep: float,
    duration_s: float,
) -> RunResult:
    """The RunResult of one run; a failed run (`failure` set) returns no numbers.

    Args:
        d31, d31_times_s: Delta31 (rad) and time (s) at each leg-1 touchdown.
        series: the recorded time series (views into the recorder: copied here);
            `RunSeries.none()` when the run was not recorded.
        touchdowns, touchdown_phases, liftoffs: per leg, the events' times (s) and the phase
            at touchdown before eq. 4 (rad).
        slips: each stance's foot slip as a share of the stroke.
        retouches: stance feet that left the ground and pressed in again (contact chatter).
        phi_aep: 2 pi (1 - beta) at the end of the run (a ramped run gets a rough landing
            share); duration_s: the run's length (the landing share skips its first third).
    """
    if failure is not None:
        return RunResult.failed(spec, integrator, dt_s, control_dt_s, failure, duration_s)
    ser = series.copy()
    events = RunEvents(
        d31=np.array(d31),
        d31_times_s=np.array(d31_times_s),
        touchdowns_s=tuple(np.array(t) for t in touchdowns),
        touchdown_phases=tuple(np.array(t) for t in touchdown_phases),
        liftoffs_s=tuple(np.array(t) for t in liftoffs),
    )
    settle = gait.settling(events.d31)
    speed = gait.forward_speed(ser.times_s, ser.body_pos_m, ser.body_quat)
    tds, los = events.touchdowns_s, events.liftoffs_s
    # the footfall walked over the settled quarter names the gait
    d31_t = events.d31_times_s
    quarter = (d31_t[-settle.tail], d31_t[-1]) if settle.tail else (0.0, 0.0)
    name = gait.run_gait(settle, gait.measured_footfall(tds, los, *quarter))
    ntd = sum(t.size for t in tds)
    duty = gait.duty_factor(ser.stance)
    landing = gait.landing_share(tds, events.touchdown_phases, phi_aep, after_s=duration_s / 3)
    retouch = float(retouches) / ntd if ntd else None
    warnings = gait.run_warnings(
        beta=spec.beta, duty_factor=duty, landing=landing, integrator=integrator, dt_s=dt_s,
        converged_dt_s=CONVERGED_DT_S, retouches=retouch,
    )  # fmt: skip
    measures = RunMeasures(
        d31_final=gait.final_d31(events.d31),
        gait=name,
        settled=settle.settled,
        drift_per_cycle=settle.drift,
        settled_why=settle.why,
        duration_s=duration_s,
        speed_cm_s=None if speed is None else speed * 100.0,
        duty_factor_measured=duty,
        slip_fraction=float(np.median(slips)) if slips else None,
        landing_swing_share=landing,
        retouches_per_stance=retouch,
        warnings=tuple(warnings),
    )
    return RunResult(spec, integrator, dt_s, control_dt_s, events, ser, measures)


# a batch that keeps no time series gives its results these (empty) ones
NOT_RECORDED = RunSeries.none()


class Recorder:
    """The time series a batch keeps (body pose and velocity, stance), one row every `every`
    control periods; preallocated for the longest run, so recording never allocates.

    With `ring`, a batch of one keeps only its last `nrec` rows, overwriting the oldest: the
    bounded history a live simulation that runs forever reads (`Simulation`)."""

    def __init__(self, n: int, nrec: int, every: int, ring: bool = False) -> None:
        if ring and n != 1:
            raise ValueError("a ring record keeps one simulation's history")
        self.every = every
        self.ring = ring
        self.n_rows = 0  # rows taken so far (in a ring, more than it holds)
        self.t = np.zeros(nrec)
        self.stance = np.zeros((n, nrec, 6), dtype=np.bool_)
        self.pos = np.zeros((n, nrec, 3))
        self.vel = np.zeros((n, nrec, 3))
        self.quat = np.zeros((n, nrec, 4))
        self.length = np.zeros(n, dtype=np.int64)  # rows each simulation has (stops on failure)

    def take(
        self,
        time_s: float,
        live: np.ndarray,
        stance: np.ndarray,
        qpos: np.ndarray,
        qvel: np.ndarray,
    ) -> None:
        """One row for the simulations `live`, from the batch's (n, ...) state arrays."""
        k = self.n_rows
        cap = self.t.shape[0]
        if k >= cap:
            if not self.ring:
                return
            k %= cap
        self.t[k] = time_s
        self.stance[live, k] = stance[live] != 0
        self.pos[live, k] = qpos[live, 0:3]
        self.vel[live, k] = qvel[live, 0:3]
        self.quat[live, k] = qpos[live, 3:7]
        self.length[live] = k + 1
        self.n_rows += 1

    def series(self, i: int) -> RunSeries:
        """Simulation i's rows in time order (views, not copies, until a ring has wrapped)."""
        if self.ring and self.n_rows > self.t.shape[0]:
            return self.since(i, None)
        n = int(self.length[i])
        return RunSeries(self.t[:n], self.stance[i, :n], self.pos[i, :n], self.vel[i, :n],
                      self.quat[i, :n])  # fmt: skip

    def since(self, i: int, after_s: float | None) -> RunSeries:
        """Simulation i's rows later than `after_s` (all of them for None), in time order;
        copies only the rows asked for (a live viewer asks every frame)."""
        cap = self.t.shape[0]
        if self.ring and self.n_rows > cap:
            order = (self.n_rows + np.arange(cap)) % cap
        else:
            order = np.arange(int(self.length[i]))
        if after_s is not None:
            order = order[int(np.searchsorted(self.t[order], after_s, side="right")) :]
        return RunSeries(self.t[order], self.stance[i, order], self.pos[i, order],
                      self.vel[i, order], self.quat[i, order])  # fmt: skip


class EventJournal:
    """What happened, per simulation: touchdowns (time, phase before eq. 4), lift-offs, Delta31
    at each leg-1 touchdown, and each stance's foot slip as a share of the stroke. Appended
    from the controller's per-period event arrays (NaN = no event), in time order."""

    def __init__(self, n: int, stroke: float) -> None:
        self.stroke = stroke
        self.touchdowns: list[list[list[float]]] = [[[] for _ in range(6)] for _ in range(n)]
        # phase of each touchdown before resetting: phi_AEP minus it is the reset's jump
        self.touchdown_phases: list[list[list[float]]] = [[[] for _ in range(6)] for _ in range(n)]
        self.liftoffs: list[list[list[float]]] = [[[] for _ in range(6)] for _ in range(n)]
        self.d31_t: list[list[float]] = [[] for _ in range(n)]
        self.d31_v: list[list[float]] = [[] for _ in range(n)]
        self.slips: list[list[float]] = [[] for _ in range(n)]
        self._td_xy = np.zeros((n, 6, 2))

    def collect(
        self,
        ids: np.ndarray,
        td_time: np.ndarray,
        td_phase: np.ndarray,
        lo_time: np.ndarray,
        d31: np.ndarray,
        feet_xy: np.ndarray,
    ) -> None:
        """This period's events of the simulations `ids`.

        Args:
            ids: (m,) simulation indices; row r of `td_time`, `lo_time`, `feet_xy` is ids[r].
            td_time, lo_time: (m, 6) touchdown / lift-off time (s) this period, NaN if none.
            td_phase, d31: (n, 6) phase at touchdown and (n,) Delta31 at a leg-1 touchdown,
                indexed by simulation.
            feet_xy: (m, 6, 2) foot positions at the period's last substep (m).
        """
        for r, leg in zip(*np.nonzero(np.isfinite(td_time)), strict=True):
            s = int(ids[r])
            self.touchdowns[s][leg].append(float(td_time[r, leg]))
            self.touchdown_phases[s][leg].append(float(td_phase[s, leg]))
            self._td_xy[s, leg] = feet_xy[r, leg]
            if leg == 0:
                self.d31_t[s].append(float(td_time[r, 0]))
                self.d31_v[s].append(float(d31[s]))
        for r, leg in zip(*np.nonzero(np.isfinite(lo_time)), strict=True):
            s = int(ids[r])
            self.liftoffs[s][leg].append(float(lo_time[r, leg]))
            if self.touchdowns[s][leg]:
                slip = float(np.hypot(*(feet_xy[r, leg] - self._td_xy[s, leg])))
                self.slips[s].append(slip / self.stroke)

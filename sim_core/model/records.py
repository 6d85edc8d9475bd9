"""A finished run's raw records -> `RunResult`: the gait measures computed once, here.

The runner keeps what happened (touchdowns, lift-offs, Delta31 at leg-1 touchdowns, the
recorded body state); what they mean (where the run ended, speed, duty factor, slip, landing
share, contact chatter) is computed by `model.gait` when a result is asked for.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from sim_core.model import gait
from sim_core.model.params import ModelParams
from sim_core.model.spec import RunFailure, RunResult, RunSpec

# the step docs/NUMERICS.md measured converged; a run on a coarser one says so in its warnings
CONVERGED_DT_S = ModelParams().dt


def _copy(a: np.ndarray | None, shape: tuple[int, ...], dtype: type = float) -> np.ndarray:
    return np.zeros(shape, dtype=dtype) if a is None else a.copy()


def assemble_result(
    *,
    spec: RunSpec,
    integrator: str,
    dt_s: float,
    control_dt_s: float,
    failure: RunFailure | None,
    d31: Sequence[float],
    d31_times_s: Sequence[float],
    times_s: np.ndarray | None,
    stance: np.ndarray | None,
    body_pos_m: np.ndarray | None,
    body_vel_m_s: np.ndarray | None,
    body_quat: np.ndarray | None,
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
        times_s, stance, body_pos_m, body_vel_m_s, body_quat: the recorded time series, (T,),
            (T, 6), (T, 3), (T, 3), (T, 4); None when the run was not recorded.
        touchdowns, touchdown_phases, liftoffs: per leg, the events' times (s) and the phase
            at touchdown before eq. 4 (rad).
        slips: each stance's foot slip as a share of the stroke.
        retouches: stance feet that left the ground and pressed in again (contact chatter).
        phi_aep: 2 pi (1 - beta) at the end of the run (a ramped run gets a rough landing
            share); duration_s: the run's length (the landing share skips its first third).
    """
    empty = np.zeros(0)
    base: dict[str, Any] = {
        "spec": spec,
        "integrator": integrator,
        "dt_s": dt_s,
        "control_dt_s": control_dt_s,
        "duration_s": duration_s,
    }
    if failure is not None:
        return RunResult(
            **base, d31=empty, d31_times_s=empty, times_s=empty,
            stance=np.zeros((0, 6), dtype=np.bool_), body_pos_m=np.zeros((0, 3)),
            body_vel_m_s=np.zeros((0, 3)), body_quat=np.zeros((0, 4)),
            touchdowns=tuple(empty for _ in range(6)),
            touchdown_phases=tuple(empty for _ in range(6)),
            liftoffs=tuple(empty for _ in range(6)), d31_final=None, gait=None,
            speed_cm_s=None, duty_factor_measured=None, slip_fraction=None, failure=failure,
        )  # fmt: skip
    times = _copy(times_s, (0,))
    st = _copy(stance, (0, 6), np.bool_)
    pos = _copy(body_pos_m, (0, 3))
    d31_arr = np.array(d31)
    d31_t = np.array(d31_times_s)
    settle = gait.settling(d31_arr)
    d31_final = gait.final_d31(d31_arr)
    quat = _copy(body_quat, (0, 4))
    speed = gait.forward_speed(times, pos, quat)
    tds = tuple(np.array(t) for t in touchdowns)
    tdp = tuple(np.array(t) for t in touchdown_phases)
    los = tuple(np.array(t) for t in liftoffs)
    # the footfall walked over the settled quarter names the gait
    quarter = (d31_t[-settle.tail], d31_t[-1]) if settle.tail else (0.0, 0.0)
    name = gait.run_gait(settle, gait.measured_footfall(tds, los, *quarter))
    ntd = sum(t.size for t in tds)
    duty = gait.duty_factor(st)
    landing = gait.landing_share(tds, tdp, phi_aep, after_s=duration_s / 3)
    retouch = float(retouches) / ntd if ntd else None
    warnings = gait.run_warnings(
        beta=spec.beta, duty_factor=duty, landing=landing, integrator=integrator, dt_s=dt_s,
        converged_dt_s=CONVERGED_DT_S, retouches=retouch,
    )  # fmt: skip
    return RunResult(
        **base,
        d31=d31_arr,
        d31_times_s=d31_t,
        times_s=times,
        stance=st,
        body_pos_m=pos,
        body_vel_m_s=_copy(body_vel_m_s, (0, 3)),
        body_quat=quat,
        touchdowns=tds,
        touchdown_phases=tdp,
        liftoffs=los,
        d31_final=d31_final,
        gait=name,
        settled=settle.settled,
        drift_per_cycle=settle.drift,
        settled_why=settle.why,
        speed_cm_s=None if speed is None else speed * 100.0,
        duty_factor_measured=duty,
        slip_fraction=float(np.median(slips)) if slips else None,
        retouches_per_stance=retouch,
        landing_swing_share=landing,
        warnings=tuple(warnings),
    )


class Series(NamedTuple):
    """One simulation's recorded time series; all None when the run was not recorded."""

    times_s: np.ndarray | None  # (T,)
    stance: np.ndarray | None  # (T, 6) bool
    body_pos_m: np.ndarray | None  # (T, 3)
    body_vel_m_s: np.ndarray | None  # (T, 3)
    body_quat: np.ndarray | None  # (T, 4) w, x, y, z


NOT_RECORDED = Series(None, None, None, None, None)


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

    def series(self, i: int) -> Series:
        """Simulation i's rows in time order (views, not copies, until a ring has wrapped)."""
        if self.ring and self.n_rows > self.t.shape[0]:
            return self.since(i, None)
        n = int(self.length[i])
        return Series(self.t[:n], self.stance[i, :n], self.pos[i, :n], self.vel[i, :n],
                      self.quat[i, :n])  # fmt: skip

    def since(self, i: int, after_s: float | None) -> Series:
        """Simulation i's rows later than `after_s` (all of them for None), in time order;
        copies only the rows asked for (a live viewer asks every frame)."""
        cap = self.t.shape[0]
        if self.ring and self.n_rows > cap:
            order = (self.n_rows + np.arange(cap)) % cap
        else:
            order = np.arange(int(self.length[i]))
        if after_s is not None:
            order = order[int(np.searchsorted(self.t[order], after_s, side="right")) :]
        return Series(self.t[order], self.stance[i, order], self.pos[i, order],
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

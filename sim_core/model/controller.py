"""The pattern-formation layer: phases -> tip targets -> joint targets, and touch -> resets.

The controller runs once per control period h (= k physics steps) for every simulation of a
batch, compiled with numba so that a single simulation is not dominated by Python overhead:

1. `plan_block` advances the oscillators over h (eq. 1 without resetting) and computes joint
   targets at the start and the end of the period from the leg kinematics and inverse
   kinematics: the set-point q*(t0) and the desired velocity (q*(t0 + h) - q*(t0)) / h.
   MuJoCo's actuators (see mjspec.py) ramp the set-point linearly through the period and apply
   kp (q* - q) + kd (dq*/dt - dq/dt), the damping part implicit in time.
2. MuJoCo runs the k substeps (`Batch.rollout`), recording the feet's positions each substep.
3. `apply_events` finds each swing leg's first touch in the period that passes the scuff rule,
   switches it to stance and resets its phase (eq. 4) *at the touchdown instant*: the phase is
   set to phi_AEP plus the advance since the touchdown substep, so the reset does not depend on
   the control period. Stance legs that reach 2 pi lift off. Delta31 is sampled after leg 1's
   touchdown.

Rules (documented in docs/MODEL.md):
- scuff: a touch while s = phi/phi_AEP < scuff_fraction (just after lift-off) is ignored;
- late landing: a swing leg past the AEP keeps moving along the AEP->PEP line; if it reaches
  the PEP (phi = 2 pi) untouched, the phase wraps and a new swing begins (a missed step).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from sim_core.model.cpg import advance_phases, reset_phase
from sim_core.model.gait import TWO_PI
from sim_core.model.legs import (
    LegGeometry,
    inverse_kinematics,
    stance_point,
    swing_point,
    tilt_matrix,
    to_body,
)


class LegState(NamedTuple):
    """Per simulation and leg, what the controller keeps between periods (n simulations).

    numba takes NamedTuples of arrays, so the kernels take a handful of grouped arguments."""

    phi: np.ndarray  # (n, 6) phase at the start of the period, [0, 2 pi)
    phi_next: np.ndarray  # (n, 6) phase at the end of the period before events, unwrapped
    stance: np.ndarray  # (n, 6) int8: 1 in stance
    lp: np.ndarray  # (n, 6, 3) landing position of the current stance, body frame, m
    phi_td: np.ndarray  # (n, 6) phase right after the current stance's touchdown (eq. 4)
    prev_height: np.ndarray  # (n, 6) foot clearance one substep before the period, m
    lifted: np.ndarray  # (n, 6) bool: a stance foot that rose above lift_clearance
    retouches: np.ndarray  # (n,) int64: lifted stance feet that pressed in again


class Drive(NamedTuple):
    """Per simulation, what beta sets through eq. 2, whether eq. 4 is on, and the drift
    surface's pin (`cpg.pin`; an instrument, off where pin_gain is 0) (n,)."""

    omega: np.ndarray  # basic frequency, rad/s
    phi_aep: np.ndarray  # 2 pi (1 - beta), rad
    reset: np.ndarray  # bool: phase resetting at touchdown
    pin_d31: np.ndarray  # the held Delta31 = Delta53, rad
    pin_gain: np.ndarray  # the pin's K, 1/s; 0: no pin


class TouchRules(NamedTuple):
    """What counts as a touchdown (docs/MODEL.md): scalars shared by the batch."""

    radius: float  # foot sphere radius, m
    touch_depth: float  # a foot touches when pressed this far in, m
    scuff_fraction: float  # touches while phi < scuff_fraction phi_AEP are ignored
    interpolate: bool  # landing instant at the clearance's zero crossing (else the substep)
    lift_clearance: float  # a stance foot this high has left the ground (chatter count), m


class EventLog(NamedTuple):
    """What happened in the last period, per simulation; NaN where nothing did."""

    td_time: np.ndarray  # (n, 6) touchdown instant, s
    td_phase: np.ndarray  # (n, 6) phase at touchdown before eq. 4, rad
    lo_time: np.ndarray  # (n, 6) lift-off instant, s
    d31: np.ndarray  # (n,) Delta31 right after leg 1's touchdown, rad


@njit(cache=True)
def _leg_target(
    geo: LegGeometry,
    leg: int,
    phi: float,
    in_stance: bool,
    phi_td: float,
    phi_aep: float,
    lp: np.ndarray,
    tip: np.ndarray,
    q: np.ndarray,
    tilt: np.ndarray,
    level: bool,
) -> None:
    if in_stance:
        stance_point(geo, leg, phi, phi_td, lp, tip)
    else:
        swing_point(geo, leg, phi, phi_aep, tip)
    if level:  # ModelParams.trajectory_frame "level": the curves do not pitch or roll
        c = geo.attach  # about the leg's own hip: the hip keeps its height over the foot
        for m in range(3):
            tip[m] -= c[leg, m]
        to_body(tilt, tip)
        for m in range(3):
            tip[m] += c[leg, m]
    inverse_kinematics(geo, leg, tip, q)


@njit(cache=True)
def plan_block(
    ids: np.ndarray,
    st: LegState,
    drive: Drive,
    k_contra: float,
    k_ipsi: float,
    h: float,
    geo: LegGeometry,
    lead: np.ndarray,
    act: np.ndarray,
    ctrl: np.ndarray,
    qpos: np.ndarray,
) -> None:
    """For the simulations in ids: the set-points q*(t0) + lead dq*/dt into MuJoCo's actuator
    states act (n, 18) (lead = kd/kp per joint folds the feed-forward into the set-point, see
    mjspec.py), the velocities dq*/dt into its controls ctrl (n, 18), and the phases
    st.phi_next (n, 6) at the end of the period without resetting. Writing MuJoCo's arrays
    here, not through numpy, saves a few microseconds a period (one simulation). qpos (n, nq)
    is read only for trajectories in the level frame (the body's attitude at t0, held over
    the period)."""
    scratch = np.empty((2, 6))
    tip = np.empty(3)
    q0 = np.empty(3)
    q1 = np.empty(3)
    tilt = np.eye(3)
    level = geo.level
    phi, phi_next, stance, lp, phi_td = st.phi, st.phi_next, st.stance, st.lp, st.phi_td
    phi_aep = drive.phi_aep
    for r in range(ids.shape[0]):
        s = ids[r]
        advance_phases(phi[s], drive.omega[s], k_contra, k_ipsi, drive.pin_d31[s],
                       drive.pin_gain[s], h, phi_next[s], scratch)  # fmt: skip
        if level:
            tilt_matrix(qpos[s, 3:7], tilt)
        for leg in range(6):
            on = stance[s, leg] != 0
            ph_td = phi_td[s, leg]
            _leg_target(geo, leg, phi[s, leg], on, ph_td, phi_aep[s], lp[s, leg], tip, q0, tilt,
                        level)  # fmt: skip
            _leg_target(geo, leg, phi_next[s, leg], on, ph_td, phi_aep[s], lp[s, leg], tip, q1,
                        tilt, level)  # fmt: skip
            for m in range(3):
                a = 3 * leg + m
                v = (q1[m] - q0[m]) / h
                act[s, a] = q0[m] + lead[a] * v
                ctrl[s, a] = v


@njit(cache=True)
def apply_events(
    ids: np.ndarray,
    height: np.ndarray,
    t0: float,
    dt: float,
    st: LegState,
    drive: Drive,
    rules: TouchRules,
    geo: LegGeometry,
    log: EventLog,
) -> int:
    """Advance st.phi to st.phi_next, applying touchdowns (with eq. 4, `reset_phase`) and
    lift-offs; returns how many happened (touchdowns plus lift-offs, so the caller can skip its
    bookkeeping at 0).

    height: (len(ids), k, >= 6) foot centre height of each leg's foot (the first six entries)
    at the start of each substep, i.e. at t0 + j dt; its clearance is height - radius.
    st.prev_height is the clearance one substep before t0 and is updated here. The foot
    touches when its clearance is below -touch_depth (it presses into the ground: the contact
    is carrying load); the landing instant is where the clearance crossed zero, interpolated
    linearly between substeps, so that it does not move with the timestep. `log` is rewritten:
    NaN where nothing happened.

    Contact chatter is counted, not acted on: a stance foot that rises more than
    lift_clearance above the ground is marked in st.lifted, and when it presses into the
    ground again st.retouches counts one more re-touch.
    """
    phi, phi_next, stance, lp, phi_td = st.phi, st.phi_next, st.stance, st.lp, st.phi_td
    prev_height, lifted, retouches = st.prev_height, st.lifted, st.retouches
    phi_aep, reset = drive.phi_aep, drive.reset
    radius, touch_depth, scuff_fraction = rules.radius, rules.touch_depth, rules.scuff_fraction
    interpolate, lift_clearance = rules.interpolate, rules.lift_clearance
    td_time, td_phase, lo_time, d31 = log.td_time, log.td_phase, log.lo_time, log.d31
    nsub = height.shape[1]
    h = nsub * dt
    tip = np.empty(3)
    events = 0
    for r in range(ids.shape[0]):
        s = ids[r]
        d31[s] = np.nan
        for leg in range(6):
            td_time[s, leg] = np.nan
            td_phase[s, leg] = np.nan
            lo_time[s, leg] = np.nan
            p0 = phi[s, leg]
            p1 = phi_next[s, leg]
            if stance[s, leg] != 0:
                for j in range(nsub):
                    c = height[r, j, leg] - radius
                    if lifted[s, leg]:
                        if c < -touch_depth:
                            lifted[s, leg] = False
                            retouches[s] += 1
                    elif c > lift_clearance:
                        lifted[s, leg] = True
            if stance[s, leg] == 0:
                for j in range(nsub):
                    if height[r, j, leg] - radius > -touch_depth:
                        continue
                    ph = p0 + (p1 - p0) * (j / nsub)
                    ph_w = ph - TWO_PI if ph >= TWO_PI else ph
                    if ph_w < scuff_fraction * phi_aep[s]:
                        continue  # scuff just after lift-off (or after a missed step)
                    # landing instant: the last zero crossing of the clearance up to substep j
                    frac = float(j)  # in substeps from t0
                    for i in range(j if interpolate else -1, -1, -1):
                        below = height[r, i, leg] - radius
                        above = prev_height[s, leg] if i == 0 else height[r, i - 1, leg] - radius
                        if above > 0.0 >= below:
                            frac = (i - 1) + above / (above - below)
                            break
                    ph = p0 + (p1 - p0) * (frac / nsub)
                    ph_w = ph - TWO_PI if ph >= TWO_PI else ph
                    swing_point(geo, leg, ph_w, phi_aep[s], tip)
                    line_z = geo.aep[leg, 2]
                    tip[2] = line_z + geo.landing_kept * (tip[2] - line_z)
                    for m in range(3):
                        lp[s, leg, m] = tip[m]
                    stance[s, leg] = 1
                    lifted[s, leg] = False
                    events += 1
                    td_time[s, leg] = t0 + frac * dt
                    td_phase[s, leg] = ph_w
                    advance = p1 - ph
                    phi_td[s, leg] = reset_phase(ph_w, phi_aep[s], reset[s])  # eq. 4
                    p1 = phi_td[s, leg] + advance
                    break
                if stance[s, leg] == 0 and p1 >= TWO_PI:
                    p1 -= TWO_PI  # missed step: the PEP was reached untouched, swing again
            elif p1 >= TWO_PI:
                lo_time[s, leg] = t0 + h * (TWO_PI - p0) / (p1 - p0)
                stance[s, leg] = 0
                events += 1
                p1 -= TWO_PI
            phi[s, leg] = p1 % TWO_PI
            prev_height[s, leg] = height[r, nsub - 1, leg] - radius
        if not math.isnan(td_time[s, 0]):
            d31[s] = (phi[s, 2] - phi[s, 0]) % TWO_PI
    return events


@njit(cache=True)
def initial_targets(
    phi: np.ndarray,
    stance: np.ndarray,
    lp: np.ndarray,
    phi_td: np.ndarray,
    phi_aep: float,
    geo: LegGeometry,
    q: np.ndarray,
    tips: np.ndarray,
) -> None:
    """Joint angles q (18,) and tip targets (6, 3) of one simulation's current phases."""
    qq = np.empty(3)
    level = np.eye(3)  # a new walk starts level: both frames agree
    for leg in range(6):
        _leg_target(geo, leg, phi[leg], stance[leg] != 0, phi_td[leg], phi_aep, lp[leg],
                    tips[leg], qq, level, False)  # fmt: skip
        for m in range(3):
            q[3 * leg + m] = qq[m]

"""Touch handling: touchdown, the scuff rule, resetting (eq. 4), lift-off; the frame of the
tip targets."""

import math

import mujoco
import numpy as np

from sim_core import ModelParams
from sim_core.model.controller import (
    Drive,
    EventLog,
    LegState,
    TouchRules,
    apply_events,
    plan_block,
)
from sim_core.model.legs import forward_kinematics, leg_geometry

P = ModelParams()
GEO = leg_geometry(P)
BETA = 0.66
PHI_AEP = 2 * math.pi * (1 - BETA)
DT = 5e-5
NSUB = 10
# radius 0: the heights below are the feet's clearances
RULES = TouchRules(
    0.0, P.oscillators.touch_depth, P.oscillators.scuff_fraction, True, P.oscillators.lift_clearance
)


def _drive(reset: bool) -> Drive:
    return Drive(np.array([1.0]), np.array([PHI_AEP]), np.array([reset]), np.zeros(1), np.zeros(1))


def _log() -> EventLog:
    return EventLog(np.empty((1, 6)), np.empty((1, 6)), np.empty((1, 6)), np.empty(1))


def _run(phi0: np.ndarray, phi1: np.ndarray, stance: np.ndarray, touch: np.ndarray, reset: bool):
    ids = np.array([0])
    # the foot is 0.1 mm up until the touch, 0.01 mm into the ground from then on
    height = np.where(touch > 0, -1e-5, 1e-4)
    prev = np.full((1, 6), 1e-4)
    phi = phi0[None].copy()
    phi_next = phi1[None].copy()
    st = stance[None].astype(np.int8).copy()
    lp = np.zeros((1, 6, 3))
    phi_td = np.full((1, 6), PHI_AEP)
    state = LegState(phi, phi_next, st, lp, phi_td, prev, np.zeros((1, 6), np.bool_),
                     np.zeros(1, np.int64))  # fmt: skip
    log = _log()
    td, lo, d31 = log.td_time, log.lo_time, log.d31
    events = apply_events(ids, height[None], 1.0, DT, state, _drive(reset), RULES,
                          GEO, log)  # fmt: skip
    assert events == np.isfinite(td).sum() + np.isfinite(lo).sum()
    return phi[0], st[0], td[0], lo[0], phi_td[0], d31[0]


def _touch(leg: int, substep: int) -> np.ndarray:
    t = np.zeros((NSUB, 6))
    t[substep:, leg] = 1e-2
    return t


def test_touchdown_resets_phase_to_aep_plus_elapsed() -> None:
    phi0 = np.full(6, 0.9 * PHI_AEP)
    phi1 = phi0 + 0.01
    phi, st, td, _, phi_td, d31 = _run(phi0, phi1, np.zeros(6, bool), _touch(0, 3), reset=True)
    assert st[0] == 1 and st[1:].sum() == 0
    frac = 2 + 1e-4 / 1.1e-4  # the clearance crosses zero between substeps 2 and 3
    assert math.isclose(td[0], 1.0 + frac * DT)
    advance_after = 0.01 * (NSUB - frac) / NSUB
    assert math.isclose(phi[0], PHI_AEP + advance_after, abs_tol=1e-12)
    assert phi_td[0] == PHI_AEP
    assert math.isclose(d31, (phi[2] - phi[0]) % (2 * math.pi))
    assert np.isnan(td[1:]).all()


def test_without_reset_the_phase_runs_on() -> None:
    phi0 = np.full(6, 0.9 * PHI_AEP)
    phi1 = phi0 + 0.01
    phi, st, _, _, phi_td, _ = _run(phi0, phi1, np.zeros(6, bool), _touch(0, 3), reset=False)
    assert st[0] == 1
    np.testing.assert_allclose(phi, phi1)
    assert math.isclose(phi_td[0], phi0[0] + 0.01 * (2 + 1e-4 / 1.1e-4) / NSUB)


def test_scuff_right_after_liftoff_is_ignored() -> None:
    phi0 = np.full(6, 0.1 * PHI_AEP)
    phi, st, td, _, _, _ = _run(phi0, phi0 + 0.01, np.zeros(6, bool), _touch(2, 0), reset=True)
    assert st.sum() == 0 and np.isnan(td).all()
    np.testing.assert_allclose(phi, phi0 + 0.01)


def test_stance_leg_lifts_off_at_pep() -> None:
    phi0 = np.full(6, 2 * math.pi - 0.004)
    phi1 = phi0 + 0.01
    phi, st, _, lo, _, _ = _run(phi0, phi1, np.ones(6, bool), np.zeros((NSUB, 6)), reset=True)
    assert st.sum() == 0
    np.testing.assert_allclose(phi, 0.006, atol=1e-12)
    np.testing.assert_allclose(lo, 1.0 + NSUB * DT * 0.4)


def test_missed_step_starts_a_new_swing() -> None:
    phi0 = np.full(6, 2 * math.pi - 0.004)
    phi, st, td, _, _, _ = _run(phi0, phi0 + 0.01, np.zeros(6, bool), np.zeros((NSUB, 6)), True)
    assert st.sum() == 0 and np.isnan(td).all()
    np.testing.assert_allclose(phi, 0.006, atol=1e-12)


def _retouches(clearance: np.ndarray) -> int:
    """Re-touches counted for leg 0 in stance over one period with the given clearances."""
    phi = np.full((1, 6), PHI_AEP + 0.1)
    height = np.zeros((1, NSUB, 6))
    height[0, :, 0] = clearance
    count = np.zeros(1, np.int64)
    state = LegState(phi, phi + 0.01, np.ones((1, 6), np.int8), np.zeros((1, 6, 3)),
                     np.full((1, 6), PHI_AEP), np.zeros((1, 6)), np.zeros((1, 6), np.bool_),
                     count)  # fmt: skip
    apply_events(np.array([0]), height, 1.0, DT, state, _drive(True), RULES, GEO,
                 _log())  # fmt: skip
    return int(count[0])


def test_a_stance_foot_that_leaves_the_ground_and_comes_back_is_a_retouch() -> None:
    pressed, up = -1e-5, 3 * P.oscillators.lift_clearance
    assert _retouches(np.array([pressed, up, up, pressed, pressed, up, pressed, 0, 0, 0])) == 2
    # hovering below the lift clearance, or leaving without coming back, is no re-touch
    assert (
        _retouches(np.full(NSUB, 0.5 * P.oscillators.lift_clearance) * np.resize([1, -1], NSUB))
        == 0
    )
    assert _retouches(np.array([pressed] * 5 + [up] * 5)) == 0


def _plan(p: ModelParams, quat: np.ndarray) -> np.ndarray:
    """plan_block's set-points (18,) for one simulation with the body at attitude `quat`."""
    geo = leg_geometry(p)
    phi = np.linspace(0.3, 5.9, 6)[None]
    st = LegState(phi.copy(), np.zeros((1, 6)), (phi >= PHI_AEP).astype(np.int8),
                  np.tile(geo.aep.reshape(1, 6, 3), (1, 1, 1)), np.full((1, 6), PHI_AEP),
                  np.zeros((1, 6)), np.zeros((1, 6), np.bool_), np.zeros(1, np.int64))  # fmt: skip
    act, ctrl = np.zeros((1, 18)), np.zeros((1, 18))
    qpos = np.zeros((1, 25))
    qpos[0, 3:7] = quat
    k = p.oscillators
    plan_block(np.array([0]), st, _drive(True), k.k_contralateral, k.k_ipsilateral, 1e-3, geo,
               np.zeros(18), act, ctrl, qpos)  # fmt: skip
    return act[0]


def test_level_frame_trajectories_keep_each_foot_target_level_under_the_hip() -> None:
    """trajectory_frame 'level' (audit row 4): the tip targets do not pitch or roll with the
    body; 'body' (the default) ignores the body's attitude entirely."""
    roll, pitch, yaw = 0.05, -0.03, 0.4
    quat = np.empty(4)
    mujoco.mju_euler2Quat(quat, np.array([roll, pitch, yaw]), "xyz")
    level = ModelParams.of(trajectory_frame="level")
    upright = np.array([1.0, 0.0, 0.0, 0.0])
    heading_only = np.empty(4)
    mujoco.mju_euler2Quat(heading_only, np.array([0.0, 0.0, yaw]), "xyz")
    # the body frame's targets never read the attitude; level ones agree with them when level
    np.testing.assert_array_equal(_plan(P, quat), _plan(P, upright))
    np.testing.assert_allclose(_plan(level, heading_only), _plan(P, upright), atol=1e-12)
    # tilted: each commanded tip, seen from the ground's frame turned to the heading, sits
    # where the body frame's target sits on a level body, relative to its own hip
    tilted = _plan(level, quat)
    mat = np.empty(9)
    mujoco.mju_quat2Mat(mat, quat)
    rot = mat.reshape(3, 3)
    heading = math.atan2(rot[1, 0], rot[0, 0])  # the body's x axis seen from above
    c, si = math.cos(heading), math.sin(heading)
    zrot = np.array([[c, -si, 0.0], [si, c, 0.0], [0.0, 0.0, 1.0]])
    geo = leg_geometry(P)
    attach = geo.attach
    flat = _plan(P, upright)
    for leg in range(6):
        tip_t, tip_f = np.empty(3), np.empty(3)
        forward_kinematics(geo, leg, tilted[3 * leg : 3 * leg + 3], tip_t)
        forward_kinematics(geo, leg, flat[3 * leg : 3 * leg + 3], tip_f)
        seen = zrot.T @ rot @ (tip_t - attach[leg])
        np.testing.assert_allclose(seen, tip_f - attach[leg], atol=1e-9)
        assert np.abs(tip_t - tip_f).max() > 1e-5  # the tilt did move the body-frame target

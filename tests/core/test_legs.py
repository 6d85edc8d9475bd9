"""Leg trajectories (Fig. 3) and inverse kinematics, checked against MuJoCo's own kinematics."""

import math

import mujoco
import numpy as np
import pytest

from sim_core import ModelParams
from sim_core.model.legs import (
    forward_kinematics,
    inverse_kinematics,
    leg_geometry,
    stance_line,
    stance_point,
    swing_point,
)
from sim_core.research import build_model

P = ModelParams()
GEO = leg_geometry(P)
AEP, PEP = stance_line(P)
BETA = 0.66
PHI_AEP = 2 * math.pi * (1 - BETA)


def _swing(leg: int, phi: float) -> np.ndarray:
    out = np.empty(3)
    swing_point(GEO, leg, phi, PHI_AEP, out)
    return out


@pytest.mark.parametrize("leg", range(6))
def test_swing_curve_runs_pep_to_aep_and_closes_along_the_line(leg: int) -> None:
    np.testing.assert_allclose(_swing(leg, 0.0), PEP[leg], atol=1e-12)
    np.testing.assert_allclose(_swing(leg, PHI_AEP), AEP[leg], atol=1e-12)
    apex = _swing(leg, PHI_AEP / 2)
    assert apex[2] - AEP[leg, 2] == pytest.approx(P.trajectory.swing_height)
    # the stroke is D and the AEP-PEP line is parallel to the body (same height)
    assert AEP[leg, 0] - PEP[leg, 0] == pytest.approx(P.trajectory.stroke)
    assert AEP[leg, 2] == PEP[leg, 2]
    # past the AEP without touchdown: back along the line, reaching the PEP at 2 pi
    mid = _swing(leg, (PHI_AEP + 2 * math.pi) / 2)
    np.testing.assert_allclose(mid, (AEP[leg] + PEP[leg]) / 2, atol=1e-12)
    np.testing.assert_allclose(_swing(leg, 2 * math.pi), PEP[leg], atol=1e-12)


def test_the_late_descent_reading_keeps_reaching_down_past_the_aep() -> None:
    p = ModelParams.of(late_swing_descent=1.0)
    geo = leg_geometry(p)
    before, at, after = np.empty(3), np.empty(3), np.empty(3)
    eps = 1e-4
    swing_point(geo, 0, PHI_AEP - eps, PHI_AEP, before)
    swing_point(geo, 0, PHI_AEP, PHI_AEP, at)
    swing_point(geo, 0, PHI_AEP + eps, PHI_AEP, after)
    # the curve's final descent speed carries on below the line, in the same direction
    rate_in = (at[2] - before[2]) / eps
    rate_out = (after[2] - at[2]) / eps
    assert rate_in < 0 and rate_out == pytest.approx(rate_in, rel=1e-3)
    assert after[0] == pytest.approx(_swing(0, PHI_AEP + eps)[0])  # fore-aft: as before
    # our reading (the default) stays on the line exactly: no rounding sneaks in
    assert _swing(0, PHI_AEP + 0.3)[2] == AEP[0, 2]


def test_stance_is_a_straight_line_from_landing_point_to_pep() -> None:
    lp = AEP[0] + np.array([-0.3e-3, 0.0, 0.1e-3])
    pts = []
    for phi in np.linspace(PHI_AEP, 2 * math.pi, 7):
        out = np.empty(3)
        stance_point(GEO, 0, phi, PHI_AEP, lp, out)
        pts.append(out)
    pts_a = np.array(pts)
    np.testing.assert_allclose(pts_a[0], lp)
    np.testing.assert_allclose(pts_a[-1], PEP[0])
    steps = np.diff(pts_a, axis=0)
    np.testing.assert_allclose(steps, steps[0] * np.ones_like(steps), atol=1e-15)


@pytest.mark.parametrize("leg", range(6))
def test_ik_round_trip_over_a_whole_cycle(leg: int) -> None:
    q = np.empty(3)
    tip = np.empty(3)
    for phi in np.linspace(0, 2 * math.pi, 50):
        target = _swing(leg, phi)
        assert inverse_kinematics(GEO, leg, target, q)
        forward_kinematics(GEO, leg, q, tip)
        np.testing.assert_allclose(tip, target, atol=1e-12)
        assert q[1] > q[1] + q[2]  # knee up: tibia points further down than the femur


def test_ik_agrees_with_mujoco_kinematics() -> None:
    model = build_model(P)
    data = mujoco.MjData(model)
    data.qpos[3] = 1.0
    targets = np.array([_swing(leg, 0.4 * PHI_AEP) for leg in range(6)])
    for leg in range(6):
        q = np.empty(3)
        inverse_kinematics(GEO, leg, targets[leg], q)
        data.qpos[7 + 3 * leg : 10 + 3 * leg] = q
    mujoco.mj_kinematics(model, data)
    torso = data.body("torso")
    for leg, name in enumerate(["R1", "L1", "R2", "L2", "R3", "L3"]):
        world = data.site(f"{name}_foot_site").xpos
        body_frame = torso.xmat.reshape(3, 3).T @ (world - torso.xpos)
        np.testing.assert_allclose(body_frame, targets[leg], atol=1e-12)


def test_ik_reports_unreachable_targets() -> None:
    q = np.empty(3)
    far = AEP[0] + np.array([0.0, 0.0, -20e-3])
    assert not inverse_kinematics(GEO, 0, far, q)


def test_a_phase_run_backwards_past_zero_holds_the_pep() -> None:
    geo = leg_geometry(ModelParams.of(swing_shape=1.7))
    out = np.empty(3)
    swing_point(geo, 0, -0.05, PHI_AEP, out)
    assert np.isfinite(out).all()
    np.testing.assert_allclose(out, PEP[0], atol=1e-12)

"""The compiled MuJoCo model matches Table I and the paper's structure."""

import mujoco
import numpy as np
import pytest

from sim_core import ModelParams
from sim_core.contract import LEG_NAMES
from sim_core.model.mjspec import gravity_vector
from sim_core.research import build_model


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    return build_model()


def test_masses_match_table_1(model: mujoco.MjModel) -> None:
    assert model.body("torso").mass[0] == pytest.approx(3.0e-3)
    for leg in LEG_NAMES:
        assert model.body(f"{leg}_coxa").mass[0] == pytest.approx(0.05e-3)
        assert model.body(f"{leg}_femur").mass[0] == pytest.approx(0.03e-3)
        assert model.body(f"{leg}_tibia").mass[0] == pytest.approx(0.03e-3)
    assert model.body_mass.sum() == pytest.approx(3.0e-3 + 6 * 0.11e-3)


def test_link_lengths_match_table_1(model: mujoco.MjModel) -> None:
    for leg in LEG_NAMES:
        # each child body sits one parent-link length along the parent's x axis
        assert np.linalg.norm(model.body(f"{leg}_femur").pos) == pytest.approx(0.02e-2)
        assert np.linalg.norm(model.body(f"{leg}_tibia").pos) == pytest.approx(0.2e-2)
        assert np.linalg.norm(model.site(f"{leg}_foot_site").pos) == pytest.approx(1.0e-2)
    box = model.geom("torso_geom").size
    assert 2 * box[0] == pytest.approx(4.2e-2)
    assert 2 * box[1] == pytest.approx(1.0e-2)


def test_three_hinges_per_leg_and_a_pd_actuator_each(model: mujoco.MjModel) -> None:
    assert model.njnt == 1 + 18
    assert model.nu == 18 and model.na == 18  # one PD servo per joint (feed-forward in act)
    assert all(model.jnt_type[1:] == mujoco.mjtJoint.mjJNT_HINGE)
    # joint 1 turns about the vertical, joints 2 and 3 about a horizontal axis
    for leg in LEG_NAMES:
        assert abs(model.joint(f"{leg}_j1").axis[2]) == 1.0
        assert model.joint(f"{leg}_j2").axis[2] == 0.0
        assert model.joint(f"{leg}_j3").axis[2] == 0.0


def test_only_feet_can_touch_the_floor(model: mujoco.MjModel) -> None:
    floor = model.geom("floor").id
    for g in range(model.ngeom):
        if g == floor:
            continue
        can = (model.geom_contype[g] & model.geom_conaffinity[floor]) or (
            model.geom_contype[floor] & model.geom_conaffinity[g]
        )
        is_foot = model.geom(g).name.endswith("_foot")
        assert bool(can) == is_foot, model.geom(g).name
    # feet never collide with each other
    feet = [model.geom(f"{leg}_foot").id for leg in LEG_NAMES]
    assert not (model.geom_contype[feet[0]] & model.geom_conaffinity[feet[1]])


def test_slope_tilts_gravity_uphill_positive() -> None:
    g = gravity_vector(10.0)
    assert np.linalg.norm(g) == pytest.approx(9.81)
    assert g[0] < 0  # walking +x uphill: gravity pulls back
    m = build_model(ModelParams(), slope_deg=-5.0)
    assert m.opt.gravity[0] > 0


def test_sprung_tarsus_adds_a_slide_joint_per_foot_and_the_feet_still_carry_the_body() -> None:
    from sim_core import RunSpec, simulate
    from sim_core.model.mjspec import leg_qpos_addresses

    p = ModelParams.of(tarsus_stiffness=200.0, tarsus_damping=0.5)
    m = build_model(p)
    slides = [j for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_SLIDE]
    assert len(slides) == 6 and m.nq == 7 + 24
    addr = leg_qpos_addresses(m)
    assert len(set(addr.tolist())) == 18 and not set(addr.tolist()) & {
        int(m.jnt_qposadr[j]) for j in slides
    }
    # Table I masses plus the six tarsi
    assert m.body_mass.sum() == pytest.approx(
        sum(build_model(ModelParams()).body_mass) + 6 * ModelParams().legs.tarsus_mass
    )
    res = simulate(RunSpec(beta=0.66, d31_init=2.9, duration_s=0.5), p)
    assert not res.diverged
    assert (
        res.series.body_pos_m[-1, 2] > p.trajectory.stand_height / 2
    )  # standing, on compressed tarsi
    assert res.series.body_pos_m[-1, 0] > 0.003  # and walking forward


@pytest.mark.parametrize("axis", ["vertical", "tibia"])
def test_compressing_a_tarsus_moves_its_foot_up_and_vertical_means_straight_up(axis: str) -> None:
    from sim_core.model.anatomy import LEG_NAMES
    from sim_core.model.mjspec import leg_qpos_addresses, mid_stance_angles

    p = ModelParams.of(tarsus_stiffness=15.0, tarsus_damping=0.04, tarsus_axis=axis)
    m = build_model(p)
    d = mujoco.MjData(m)
    d.qpos[3] = 1.0
    d.qpos[leg_qpos_addresses(m)] = mid_stance_angles(p).ravel()  # where 'vertical' is defined
    mujoco.mj_kinematics(m, d)
    before = d.site_xpos.copy()
    for name in LEG_NAMES:
        d.qpos[m.jnt_qposadr[m.joint(f"{name}_tarsus").id]] = 1e-4
    mujoco.mj_kinematics(m, d)
    moved = (d.site_xpos - before)[:6]
    assert np.all(moved[:, 2] > 0.4e-4)  # compression lifts every foot
    if axis == "vertical":
        np.testing.assert_allclose(moved[:, 2], 1e-4, rtol=1e-3)
        assert np.abs(moved[:, :2]).max() < 1e-7
    else:  # along the tibia: part of the travel is sideways
        assert np.abs(moved[:, 1]).min() > 0.3e-4


def test_physics_model_drops_only_what_drawing_needs() -> None:
    full, bare = build_model(), build_model(visual=False)
    assert bare.ngeom == 1 + 6 and full.ngeom > bare.ngeom  # the floor and the feet collide
    assert (bare.nq, bare.nv, bare.nu, bare.nbody) == (full.nq, full.nv, full.nu, full.nbody)
    np.testing.assert_array_equal(bare.body_mass, full.body_mass)
    np.testing.assert_array_equal(bare.body_inertia, full.body_inertia)
    np.testing.assert_array_equal(bare.body_pos, full.body_pos)


def test_live_simulation_draws_the_visual_model_at_the_physics_state() -> None:
    from sim_core import RunSpec, Simulation

    sim = Simulation(RunSpec(beta=0.66))
    sim.advance(0.05)
    data = sim.data
    assert sim.model.ngeom > 7  # body box and leg capsules to draw
    np.testing.assert_allclose(data.qpos[:3], sim._runner.qpos[0, :3])
    assert data.xpos[1, 0] > 0  # poses computed for drawing

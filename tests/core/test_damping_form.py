"""The PD damping form: the velocity feed-forward share per joint group scales the set-point
lead (0 = damping on the joint velocity), and a share of 0 walks differently from the default."""

import numpy as np

from sim_core import ModelParams, RunSpec, simulate
from sim_core.model.mjspec import servo_leads

JOINT_VELOCITY = ModelParams.of(velocity_feedforward_yaw=0.0, velocity_feedforward_lift=0.0)
TRACKING = ModelParams.of(velocity_feedforward_yaw=1.0, velocity_feedforward_lift=1.0)


def test_joint_velocity_has_no_leads() -> None:
    assert np.all(servo_leads(JOINT_VELOCITY) == 0.0)
    assert np.all(servo_leads(TRACKING) > 0.0)
    default = servo_leads(ModelParams()).reshape(6, 3)  # yaw tracks, lift damps its velocity
    assert np.all(default[:, 0] > 0.0) and np.all(default[:, 1:] == 0.0)


def test_feedforward_share_scales_each_group_alone() -> None:
    base = servo_leads(TRACKING).reshape(6, 3)
    lift = servo_leads(TRACKING.replace(**{"velocity_feedforward_lift": 0.25}))
    lift = lift.reshape(6, 3)
    assert np.array_equal(lift[:, 0], base[:, 0])  # joint 1 keeps its feed-forward
    assert np.allclose(lift[:, 1:], 0.25 * base[:, 1:])
    yaw = servo_leads(TRACKING.replace(**{"velocity_feedforward_yaw": 0.5}))
    yaw = yaw.reshape(6, 3)
    assert np.allclose(yaw[:, 0], 0.5 * base[:, 0]) and np.array_equal(yaw[:, 1:], base[:, 1:])


def test_damping_forms_differ() -> None:
    spec = RunSpec(beta=0.66, d31_init=2.0, duration_s=0.5)
    a = simulate(spec, TRACKING)
    b = simulate(spec, JOINT_VELOCITY)
    assert a.error is None and b.error is None
    n = min(a.events.d31.size, b.events.d31.size)
    assert n > 0
    assert not np.allclose(a.events.d31[:n], b.events.d31[:n])


def test_support_ratio_moves_load_to_the_middle_pair_at_equal_total() -> None:
    from lab.diagnostics import support_stiffness
    from sim_core.model.mjspec import joint_gains, lift_scale

    p = ModelParams.of(support_ratio=2.0)
    assert sum(lift_scale(p, pair) for pair in (0, 1, 2)) == 3.0  # equal total
    assert joint_gains(p, "j2", 1)[0] == 2 * joint_gains(p, "j2", 0)[0]
    assert joint_gains(p, "j1", 1) == joint_gains(p, "j1", 0)  # yaw joints untouched
    assert lift_scale(ModelParams(), 1) == 1.0  # the default is the unscaled model
    base, stiff = support_stiffness(ModelParams()), support_stiffness(p)
    assert stiff["ratio_r"] > 2 * base["ratio_r"]
    rest = stiff["load_at_rest_N"]
    assert rest[2] > rest[0] and rest[3] > rest[5]  # the middle pair carries more

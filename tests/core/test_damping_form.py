"""The PD damping form option: 'joint_velocity' drops the feed-forward (leads 0) and walks
differently from the default 'tracking_error'."""

import numpy as np

from sim_core import ModelParams, RunSpec, simulate
from sim_core.model.mjspec import servo_leads


def test_joint_velocity_has_no_leads() -> None:
    assert np.all(servo_leads(ModelParams(pd_damping="joint_velocity")) == 0.0)
    assert np.all(servo_leads(ModelParams()) > 0.0)


def test_damping_forms_differ() -> None:
    spec = RunSpec(beta=0.66, d31_init=2.0, duration_s=0.5)
    a = simulate(spec)
    b = simulate(spec, ModelParams(pd_damping="joint_velocity"))
    assert a.error is None and b.error is None
    n = min(a.d31.size, b.d31.size)
    assert n > 0
    assert not np.allclose(a.d31[:n], b.d31[:n])

"""The penalty ground (`ModelParams.ground = "penalty"`, sim_core/model/ground.py): a compiled
mjcb_passive callback whose state rides in each simulation's userdata."""

from __future__ import annotations

import numpy as np
import pytest

from sim_core import ModelParams, RunSpec, simulate, simulate_batch
from sim_core.model import ground

PENALTY = ModelParams(ground="penalty")


def test_struct_offsets_are_found_and_point_at_the_fields() -> None:
    nnumeric, numeric, userdata, passive, site_xpos = ground.struct_offsets()
    assert len({numeric, userdata, passive, site_xpos}) == 4 and nnumeric < numeric


def test_the_installed_callback_leaves_the_constraint_ground_alone() -> None:
    spec = RunSpec(beta=0.62, d31_init=3.0, duration_s=0.4)
    before = simulate(spec)
    ground.install()  # global: every later step of every model calls it
    after = simulate(spec)
    assert np.array_equal(before.d31, after.d31)
    assert np.array_equal(before.body_pos_m, after.body_pos_m)


def test_a_batch_keeps_each_simulation_s_anchors() -> None:
    """Anchors live in userdata, which mujoco.batch saves with each simulation's row: a batch on
    2 threads equals each run alone, bit for bit."""
    specs = [RunSpec(beta=b, d31_init=x, duration_s=0.6) for b, x in ((0.62, 1.9), (0.7, 3.0))]
    together = simulate_batch(specs, PENALTY, nthread=2)
    for s, r in zip(specs, together, strict=True):
        alone = simulate(s, PENALTY)
        assert np.array_equal(r.d31, alone.d31)
        assert np.array_equal(r.body_pos_m, alone.body_pos_m)


def test_the_insect_stands_and_walks_on_it_without_slipping() -> None:
    r = simulate(RunSpec(beta=0.66, duration_s=1.5), PENALTY)
    assert r.failure is None and r.warnings == ()
    assert r.slip_fraction is not None and r.slip_fraction < 0.10
    height = float(np.median(r.body_pos_m[:, 2]))
    assert abs(height - PENALTY.stand_height) < 0.5e-3, height  # on its feet, not sunk
    assert r.speed_cm_s is not None and r.speed_cm_s > 2.5


def test_a_ground_too_stiff_for_the_step_fails_as_a_typed_value() -> None:
    stiff = ModelParams(ground="penalty", ground_stiffness=1e6, ground_tangential_stiffness=1e6)
    r = simulate(RunSpec(beta=0.66, duration_s=0.3), stiff)
    assert r.failure is not None and r.failure.kind in ("flipped", "on_floor", "non_finite",
                                                           "mujoco_warning", "left_ground",
                                                           "no_footholds")  # fmt: skip


@pytest.mark.parametrize("k", [2e4])
def test_a_chattering_ground_says_so(k: float) -> None:
    """2e4 N/m at 5e-5 s does not blow up: feet leave and press in 10-30 times per stance."""
    p = ModelParams(ground="penalty", ground_stiffness=k, ground_tangential_stiffness=k,
                    ground_damping=0.32, ground_tangential_damping=0.32)  # fmt: skip
    r = simulate(RunSpec(beta=0.70, d31_init=1.9, duration_s=1.5), p)
    assert r.failure is None
    assert any("chatters" in w for w in r.warnings), r.warnings

"""The grounds (`ModelParams.ground`, sim_core/model/ground.py): MuJoCo's contact constraint and
the paper's viscoelastic feet, a compiled MuJoCo engine plugin whose state rides in each
simulation's plugin_state."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest

from sim_core import ModelParams, RunSpec, simulate, simulate_batch
from sim_core.model import ground
from sim_core.research import build_model

PENALTY = ModelParams.of(ground="penalty")
REPO = Path(__file__).resolve().parents[2]


def test_one_factory_picks_the_ground_with_its_parameters() -> None:
    constraint = ground.ground_for(ModelParams())
    assert isinstance(constraint, ground.ConstraintGround)
    penalty = ground.ground_for(PENALTY)
    assert isinstance(penalty, ground.PenaltyGround)
    assert penalty.stiffness == PENALTY.contact.ground_stiffness
    # the plugin reads its numbers back with strtod: the strings name the same doubles
    config = penalty.config()
    assert float(config["stiffness"]) == PENALTY.contact.ground_stiffness
    assert float(config["radius"]) == PENALTY.legs.foot_radius
    assert len(config["sites"].split()) == ground.N_FEET


def test_each_model_carries_its_own_ground() -> None:
    m = build_model(PENALTY, visual=False)
    assert m.nplugin == 1 and m.npluginstate == 3 * ground.N_FEET  # anchors x, y, touching
    assert m.nuserdata == 0 and m.nnumeric == 0
    assert m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT
    assert not m.geom_contype.any()  # the feet collide with nothing
    c = build_model(ModelParams(), visual=False)
    assert c.nplugin == 0 and c.npluginstate == 0
    assert not c.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT
    feet = [c.geom(ground.foot_geom(leg)).id for leg in ("L1", "R3")]
    assert (c.geom_contype[feet] == 1).all() and (c.geom_priority[feet] == 1).all()


def test_a_library_from_another_source_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    ground.load_plugin()
    monkeypatch.setattr(ground.ground_build, "plugin_name", lambda: "insect_gait.stale")
    with pytest.raises(RuntimeError, match="another version"):
        ground.load_plugin.__wrapped__()


_CONSTRAINT_RUN = """
import sys
import numpy as np
from sim_core import RunSpec, simulate
r = simulate(RunSpec(beta=0.62, d31_init=3.0, duration_s=0.4))
np.savez(sys.argv[1], d31=r.events.d31, body_pos_m=r.series.body_pos_m,
         body_vel_m_s=r.series.body_vel_m_s)
"""


def test_the_constraint_ground_after_a_penalty_one_is_as_in_a_fresh_process(
    tmp_path: Path,
) -> None:
    """Nothing process-wide: a constraint-ground run after penalty-ground runs (plugin loaded,
    models with instances made and stepped) equals the same run in a fresh interpreter."""
    simulate(RunSpec(beta=0.62, d31_init=3.0, duration_s=0.2), PENALTY)
    here = simulate(RunSpec(beta=0.62, d31_init=3.0, duration_s=0.4))
    out = tmp_path / "fresh.npz"
    subprocess.run([sys.executable, "-c", _CONSTRAINT_RUN, str(out)], cwd=REPO, check=True,
                   timeout=300)  # fmt: skip
    fresh = np.load(out)
    assert fresh["d31"].size > 0
    assert np.array_equal(here.events.d31, fresh["d31"])
    for key in ("body_pos_m", "body_vel_m_s"):
        assert np.array_equal(getattr(here.series, key), fresh[key]), key


def test_a_batch_keeps_each_simulation_s_anchors() -> None:
    """Anchors live in plugin_state, which mujoco.batch saves with each simulation's row: a
    batch on 2 threads equals each run alone, bit for bit."""
    specs = [RunSpec(beta=b, d31_init=x, duration_s=0.6) for b, x in ((0.62, 1.9), (0.7, 3.0))]
    together = simulate_batch(specs, PENALTY, nthread=2)
    for s, r in zip(specs, together, strict=True):
        alone = simulate(s, PENALTY)
        assert np.array_equal(r.events.d31, alone.events.d31)
        assert np.array_equal(r.series.body_pos_m, alone.series.body_pos_m)


def test_the_insect_stands_and_walks_on_it_without_slipping() -> None:
    r = simulate(RunSpec(beta=0.66, duration_s=1.5), PENALTY)
    assert r.failure is None and r.measures.warnings == ()
    assert r.measures.slip_fraction is not None and r.measures.slip_fraction < 0.10
    height = float(np.median(r.series.body_pos_m[:, 2]))
    assert abs(height - PENALTY.trajectory.stand_height) < 0.5e-3, height  # on its feet, not sunk
    assert r.measures.speed_cm_s is not None and r.measures.speed_cm_s > 2.5


def test_a_ground_too_stiff_for_the_step_fails_as_a_typed_value() -> None:
    stiff = ModelParams.of(ground="penalty", ground_stiffness=1e6, ground_tangential_stiffness=1e6)
    r = simulate(RunSpec(beta=0.66, duration_s=0.3), stiff)
    assert r.failure is not None and r.failure.kind in ("flipped", "on_floor", "non_finite",
                                                           "mujoco_warning", "left_ground",
                                                           "no_footholds")  # fmt: skip


@pytest.mark.parametrize("k", [2e4])
def test_a_chattering_ground_says_so(k: float) -> None:
    """2e4 N/m at 5e-5 s does not blow up: feet leave and press in 10-30 times per stance."""
    p = ModelParams.of(ground="penalty", ground_stiffness=k, ground_tangential_stiffness=k,
                    ground_damping=0.32, ground_tangential_damping=0.32)  # fmt: skip
    r = simulate(RunSpec(beta=0.70, d31_init=1.9, duration_s=1.5), p)
    assert r.failure is None
    assert any("chatters" in w for w in r.measures.warnings), r.measures.warnings

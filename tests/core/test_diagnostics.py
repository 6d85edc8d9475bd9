"""Mechanism diagnostics on the full model: numbers with the properties physics demands."""

import math

import numpy as np
import pytest

from lab.diagnostics import _fit_ring, load_share, support_stiffness
from sim_core import ModelParams


def test_ring_fit_recovers_a_known_damped_oscillation() -> None:
    t = np.arange(0, 0.1, 1e-5)
    f, zeta = 60.0, 0.1
    wn = 2 * math.pi * f / math.sqrt(1 - zeta**2)
    x = np.exp(-zeta * wn * t) * np.cos(2 * math.pi * f * t)
    m = _fit_ring(t, x, "test")
    assert m.frequency_hz == pytest.approx(f, rel=0.02)
    assert m.damping_ratio == pytest.approx(zeta, rel=0.1)
    over = _fit_ring(t, np.exp(-t / 0.01), "slow")
    assert over.frequency_hz is None and over.decay_ms == pytest.approx(10.0, rel=0.05)


def test_support_is_symmetric_fore_and_hind_and_carries_the_weight() -> None:
    p = ModelParams.of(com_offset_x=0.0)  # the default's centre of mass sits 1 mm forward
    s = support_stiffness(p)
    k = s["k_pair_N_per_m"]
    assert k["fore"] == pytest.approx(k["hind"], rel=0.01)  # mirror-symmetric body and legs
    assert 0.5 < s["ratio_r"] < 2.0 and all(v > 0 for v in k.values())
    legs = 6 * (p.legs.coxa_mass + p.legs.femur_mass + p.legs.tibia_mass)
    assert sum(s["load_at_rest_N"]) == pytest.approx((p.body.body_mass + legs) * 9.81, rel=0.05)


def test_a_forward_centre_of_mass_loads_the_fore_legs() -> None:
    base = load_share(ModelParams(), betas=(0.66,), duration_s=1.2, settle_s=0.5)[0.66]
    fwd = load_share(ModelParams.of(com_offset_x=3e-3), betas=(0.66,), duration_s=1.2,
                     settle_s=0.5)[0.66]  # fmt: skip
    assert sum(base["share"].values()) == pytest.approx(1.0, abs=1e-3)
    assert fwd["share"]["fore"] > base["share"]["fore"]
    assert fwd["share"]["hind"] < base["share"]["hind"]

"""The reduced support model: converged, reset-dependent, and the landing-height lever."""

import math

import numpy as np
import pytest

from lab.reduced_model import ReducedParams, attractors, simulate_reduced


def test_without_resetting_delta31_stays_put() -> None:
    _, d = simulate_reduced(0.70, 2.5, duration_s=2.0, phase_reset=False)
    assert d.size > 15
    assert np.max(np.abs(d - 2.5)) < 1e-6


def test_stance_from_the_line_gives_a_metachronal_branch_that_moves_with_beta() -> None:
    p = ReducedParams(landing_height_kept=0.0)
    slow = attractors(0.70, n_init=6, params=p)
    fast = attractors(0.62, n_init=6, params=p)
    # starts in the lower half settle on one branch near 2 pi / 3, lower at low speed
    low_slow = [x for x in slow if x < math.pi]
    low_fast = [x for x in fast if x < math.pi]
    assert low_slow and low_fast
    assert max(low_slow) - min(low_slow) < 0.05
    assert 1.4 < np.mean(low_slow) < 2.2
    assert np.mean(low_fast) > np.mean(low_slow) + 0.1


def test_keeping_the_landing_height_removes_that_branch() -> None:
    finals = attractors(0.70, n_init=6, params=ReducedParams(landing_height_kept=1.0))
    assert not any(1.4 < x < 2.2 for x in finals)


@pytest.mark.parametrize("beta", [0.62, 0.70])
def test_half_timestep_gives_the_same_finals(beta: float) -> None:
    p = ReducedParams(landing_height_kept=0.0)
    a = attractors(beta, n_init=4, params=p)
    b = attractors(beta, n_init=4, params=ReducedParams(landing_height_kept=0.0, dt=p.dt / 2))
    assert np.max(np.abs(np.array(a) - np.array(b))) < 0.05


def test_landing_share_tells_late_landings_from_mid_swing_ones() -> None:
    from lab.reduced_model import run_reduced

    stiff = run_reduced(0.62, 2.0, duration_s=2.0, params=ReducedParams(landing_height_kept=0.0))
    soft = ReducedParams(landing_height_kept=0.0, leg_stiffness=12.0, leg_damping=0.04,
                         swing_height=1.0e-3)  # fmt: skip
    sagging = run_reduced(0.62, 2.0, duration_s=2.0, params=soft)
    # 100 N/m legs sag ~0.1 mm under a 0.8 mm swing: feet land late; 12 N/m ~1 mm: mid-swing
    assert stiff.landing_share > 0.9
    assert sagging.landing_share < 0.75
    assert stiff.d31.size == stiff.times.size > 10

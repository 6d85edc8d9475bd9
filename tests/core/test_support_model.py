"""The quasi-static support model: a sag-driven branch sits where a posterior leg lands as its
anterior neighbour lifts off, Delta31 = phi_AEP = 2 pi (1 - beta)."""

import math

import numpy as np
import pytest

from sim_core.support_model import SupportGeometry, landing_sag, quasi_static_drift, stable_points

GRID = np.linspace(1.0, 3.5, 251)


@pytest.mark.parametrize("beta", [0.62, 0.655, 0.70])
def test_sag_branch_sits_at_the_aep_phase(beta: float) -> None:
    pts = stable_points(beta, GRID)
    assert len(pts) == 1
    assert pts[0] == pytest.approx(2 * math.pi * (1 - beta), abs=0.011)


def test_weak_support_sags_more() -> None:
    # tripod, beta 0.62: every leg lands while only the other tripod stands
    sag = landing_sag(0.62, math.pi)
    assert np.all(np.isfinite(sag)) and np.all(sag > 0)
    # a centre of mass moved forward loads the fore legs: fore hips sag more than hind ones
    fwd = landing_sag(0.62, math.pi, SupportGeometry(com_x=2.0))
    assert fwd[0] - fwd[4] > sag[0] - sag[4]


def test_drift_pulls_toward_the_aep_phase_at_low_speed() -> None:
    below, above = quasi_static_drift(0.70, [1.6, 2.2])
    assert below > 0 > above

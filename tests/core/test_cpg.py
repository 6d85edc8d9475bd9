"""The oscillators follow eqs. 1, 3, 5-7 exactly; Delta31 is neutral without resetting."""

import math

import numpy as np
import pytest

from sim_core.model.cpg import (
    advance_phases,
    coupling,
    coupling_matrices,
    coupling_reference,
    initial_phases,
)

KC, KI = 32.0, 40.0


def _wrap_pi(x: np.ndarray | float) -> np.ndarray:
    return (np.asarray(x) + math.pi) % (2 * math.pi) - math.pi


def test_compiled_coupling_equals_literal_eq3() -> None:
    rng = np.random.default_rng(0)
    g = np.empty(6)
    for _ in range(200):
        phi = rng.uniform(0, 2 * math.pi, 6)
        coupling(phi, KC, KI, g)
        np.testing.assert_allclose(g, coupling_reference(phi, KC, KI), atol=1e-12)


def test_gain_matrix_is_the_papers() -> None:
    k, _ = coupling_matrices(np.zeros(6), KC, KI)
    nonzero = {(i + 1, j + 1) for i, j in zip(*np.nonzero(k), strict=True)}
    assert nonzero == {
        (1, 2), (2, 1), (3, 4), (4, 3), (5, 6), (6, 5),  # eq. 5
        (3, 1), (3, 5), (4, 2), (4, 6),  # eq. 7
    }  # fmt: skip
    assert k[0, 1] == KC and k[2, 0] == KI


def _integrate(phi: np.ndarray, seconds: float, omega: float = 40.0) -> np.ndarray:
    out = phi.copy()
    nxt = np.empty(6)
    scratch = np.empty((2, 6))
    h = 2e-4
    for _ in range(int(seconds / h)):
        advance_phases(out, omega, KC, KI, 0.0, 0.0, h, nxt, scratch)
        out[:] = nxt
    return out


def test_left_right_lock_in_antiphase() -> None:
    phi = _integrate(np.array([0.0, 0.5, 1.0, 2.0, 3.0, 3.1]), 1.0)
    for a, b in ((1, 0), (3, 2), (5, 4)):
        assert abs(_wrap_pi(phi[a] - phi[b] - math.pi)) < 1e-3


def test_eq7_makes_delta31_equal_delta53() -> None:
    phi0 = np.array([0.0, math.pi, 0.3, 0.3 + math.pi, 3.5, 3.5 + math.pi])
    phi = _integrate(phi0, 1.0)
    assert abs(_wrap_pi((phi[2] - phi[0]) - (phi[4] - phi[2]))) < 1e-3
    assert abs(_wrap_pi((phi[3] - phi[1]) - (phi[5] - phi[3]))) < 1e-3


@pytest.mark.parametrize("d31", [0.5, 2.0, 2.9, 4.0])
def test_delta31_is_neutral_without_resetting(d31: float) -> None:
    phi = _integrate(initial_phases(d31), 2.0)
    assert abs(_wrap_pi(phi[2] - phi[0] - d31)) < 1e-9


def test_initial_phases_satisfy_constraints() -> None:
    phi = initial_phases(2.0, 1.0)
    assert _wrap_pi(phi[1] - phi[0] - math.pi) == pytest.approx(0.0, abs=1e-12)
    assert _wrap_pi(phi[2] - phi[0] - 2.0) == pytest.approx(0.0, abs=1e-12)
    assert _wrap_pi(phi[4] - phi[2] - 2.0) == pytest.approx(0.0, abs=1e-12)
    g = np.empty(6)
    coupling(phi, KC, KI, g)
    np.testing.assert_allclose(g, 0.0, atol=1e-9)  # a fixed point of eqs. 3-7


def test_eq4_reset_alone() -> None:
    """Eq. 4: a landing sets the phase to phi_AEP (a jump e = phi_AEP - phi, > 0 when early);
    with resetting off the phase is untouched."""
    from sim_core.model.cpg import reset_phase

    aep = 2 * math.pi * (1 - 0.66)
    for phi in (0.6 * aep, aep, aep + 0.3):
        assert reset_phase(phi, aep, True) == aep
        assert reset_phase(phi, aep, False) == phi
    early = 0.8 * aep
    assert reset_phase(early, aep, True) - early == pytest.approx(0.2 * aep)

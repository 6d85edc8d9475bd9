"""The rhythm generator: six phase oscillators, eqs. 1, 3, 5, 6, 7, and resetting, eq. 4.

eq. 1   dphi_i/dt = omega + g1_i + g2_i
eq. 3   g1_i = - sum_j K_ij sin(Delta_ij - Delta*_ij),  Delta_ij = phi_i - phi_j
eq. 5   Delta*_21 = Delta*_43 = Delta*_65 = pi,  K12 = K21 = K34 = K43 = K56 = K65 = 32
eq. 7   Delta*_31 = Delta_53, Delta*_35 = Delta_13, Delta*_42 = Delta_64, Delta*_46 = Delta_24,
        K31 = K35 = K42 = K46 = 40, every other K zero
eq. 4   g2_i = (phi_AEP - phi_i) delta(t - t_land^i): phi_i <- phi_AEP at touchdown of leg i

Only the middle oscillators feel eq. 7, and both of their ipsilateral terms equal
sin(2 phi_m - phi_fore - phi_hind): they pull the middle phase to the mean of fore and hind.
Nothing here prefers a gait: Delta31 itself is neutral under eqs. 3-7 (Sec. II B 5).

`coupling_matrices` / `coupling_reference` spell eq. 3 out literally with 6x6 matrices and serve
as the oracle for the compiled `coupling`, which the controller calls every update.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from sim_core.model.gait import TWO_PI

# paper leg index (1-based) -> array index: leg i is index i - 1
CONTRALATERAL = ((0, 1), (2, 3), (4, 5))


def coupling_matrices(phi: np.ndarray, k_contra: float, k_ipsi: float) -> tuple[np.ndarray, ...]:
    """K and Delta* of eq. 3 for the current phases (Delta* depends on them through eq. 7)."""
    k = np.zeros((6, 6))
    dstar = np.zeros((6, 6))
    for a, b in CONTRALATERAL:
        k[a, b] = k[b, a] = k_contra
        dstar[a, b] = dstar[b, a] = math.pi  # Delta*_21 = pi and Delta*_12 = -pi = pi
    d = phi[:, None] - phi[None, :]  # Delta_ij
    # eq. 7 (0-based): Delta*_31 = Delta_53, Delta*_35 = Delta_13, Delta*_42 = Delta_64,
    # Delta*_46 = Delta_24
    for i, j, (p, q) in (
        (2, 0, (4, 2)),
        (2, 4, (0, 2)),
        (3, 1, (5, 3)),
        (3, 5, (1, 3)),
    ):
        k[i, j] = k_ipsi
        dstar[i, j] = d[p, q]
    return k, dstar


def coupling_reference(phi: np.ndarray, k_contra: float, k_ipsi: float) -> np.ndarray:
    """g1 of eq. 3, literally: -sum_j K_ij sin(Delta_ij - Delta*_ij)."""
    k, dstar = coupling_matrices(phi, k_contra, k_ipsi)
    d = phi[:, None] - phi[None, :]
    return -(k * np.sin(d - dstar)).sum(axis=1)


@njit(cache=True)
def coupling(phi: np.ndarray, k_contra: float, k_ipsi: float, g: np.ndarray) -> None:
    """g1 of eq. 3 for one simulation, written out term by term (same sums as the reference)."""
    pi = math.pi
    g[0] = -k_contra * math.sin(phi[0] - phi[1] - pi)
    g[1] = -k_contra * math.sin(phi[1] - phi[0] - pi)
    g[4] = -k_contra * math.sin(phi[4] - phi[5] - pi)
    g[5] = -k_contra * math.sin(phi[5] - phi[4] - pi)
    # middle legs: K31 sin(D31 - D53) + K35 sin(D35 - D13), both = sin(2 phi3 - phi1 - phi5)
    s3 = math.sin((phi[2] - phi[0]) - (phi[4] - phi[2]))
    s3b = math.sin((phi[2] - phi[4]) - (phi[0] - phi[2]))
    g[2] = -k_contra * math.sin(phi[2] - phi[3] - pi) - k_ipsi * s3 - k_ipsi * s3b
    s4 = math.sin((phi[3] - phi[1]) - (phi[5] - phi[3]))
    s4b = math.sin((phi[3] - phi[5]) - (phi[1] - phi[3]))
    g[3] = -k_contra * math.sin(phi[3] - phi[2] - pi) - k_ipsi * s4 - k_ipsi * s4b


@njit(cache=True)
def pin(phi: np.ndarray, d: float, gain: float, g: np.ndarray) -> None:
    """The drift surface's pin (an instrument, not the paper's model), added to g:

    fore i in {1, 2}, middle m = i + 2:  dphi_i/dt += K sin(phi_m - phi_i - D)
    hind h in {5, 6}, middle m = h - 2:  dphi_h/dt += K sin(phi_m + D - phi_h)

    Delta31 > D speeds the fore leg up (Delta31 falls), Delta53 > D slows the hind leg (Delta53
    falls). The middle oscillators keep eq. 7 alone, so S = (phi5 + phi6 - phi1 - phi2) / 4,
    which eqs. 3-7 and omega leave alone, moves only by the resets and by the pin: on a
    periodic pinned walk the pin cancels exactly the resets' drift at D.
    """
    g[0] += gain * math.sin(phi[2] - phi[0] - d)
    g[1] += gain * math.sin(phi[3] - phi[1] - d)
    g[4] += gain * math.sin(phi[2] + d - phi[4])
    g[5] += gain * math.sin(phi[3] + d - phi[5])


@njit(cache=True)
def advance_phases(
    phi: np.ndarray,
    omega: float,
    k_contra: float,
    k_ipsi: float,
    pin_d31: float,
    pin_gain: float,
    h: float,
    out: np.ndarray,
    scratch: np.ndarray,
) -> None:
    """One explicit-midpoint step of eq. 1 without resetting (g2 acts only at touchdowns).

    Phases are not wrapped here: the caller needs the unwrapped advance to locate events.
    pin_gain > 0 adds the drift surface's `pin` at pin_d31; at 0 the step is eq. 1 alone, the
    same operations as before the pin existed (bit for bit). scratch: (2, 6) work space.
    """
    g = scratch[0]
    mid = scratch[1]
    pinned = pin_gain > 0.0
    coupling(phi, k_contra, k_ipsi, g)
    if pinned:
        pin(phi, pin_d31, pin_gain, g)
    for i in range(6):
        mid[i] = phi[i] + 0.5 * h * (omega + g[i])
    coupling(mid, k_contra, k_ipsi, g)
    if pinned:
        pin(mid, pin_d31, pin_gain, g)
    for i in range(6):
        out[i] = phi[i] + h * (omega + g[i])


@njit(cache=True)
def reset_phase(phi_touchdown: float, phi_aep: float, enabled: bool) -> float:
    """Eq. 4 at leg i's touchdown: the phase right after landing.

    g2_i = (phi_AEP - phi_i) delta(t - t_land^i) integrates to a jump of e_i = phi_AEP - phi_i,
    so the phase becomes phi_AEP whenever the leg lands (e_i > 0: it landed early, before its
    swing curve reached the AEP); with resetting off (`enabled` False) it is left unchanged.
    """
    return phi_aep if enabled else phi_touchdown


def initial_phases(d31: float, phi1: float = 0.0) -> np.ndarray:
    """Phases satisfying eqs. 5-6 with the given Delta31: the paper's one-parameter gait family."""
    p1 = phi1
    p3 = p1 + d31
    p5 = p3 + d31  # Delta53 = Delta31 (eq. 6)
    phi = np.array([p1, p1 + math.pi, p3, p3 + math.pi, p5, p5 + math.pi])
    return np.mod(phi, TWO_PI)

"""A reduced dynamic support model: which gait do sag and phase resetting select by themselves?

The full model (MuJoCo) has thousands of moving parts; this one keeps only what the paper's
mechanism needs, so that its attractors can be mapped in milliseconds and read against the
full model's (docs/REPRODUCTION.md):

- the paper's six oscillators, eqs. 1, 3, 5-7 (`cpg.advance_phases`), reset at touchdown (eq. 4);
- a rigid body with heave, pitch and roll (small angles) on six vertical Kelvin-Voigt legs
  (stiffness k, damping c) at the stance-foot positions, under its weight;
- a swing foot that lands where its lift profile h sin(pi s^p) meets its sagged hip;
- a stance leg whose rest length starts from the landing height and returns to the nominal
  over the stance (`landing_height_kept` = 1, the paper's "straight line from LP to PEP" taken
  literally) or starts at the nominal at once (0).

It has no legs' own dynamics, no horizontal motion and no friction: when its attractors match
the full model's, the body's support mechanics is what selects the gait there.
SI units throughout; each call runs one simulation (compiled with numba).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from sim_core.contract import TWO_PI
from sim_core.research import advance_phases, initial_values, phi_aep

MAX_EVENTS = 4000


@dataclass(frozen=True)
class ReducedParams:
    """Defaults mirror the full model's geometry (ModelParams) and Table I's body."""

    leg_stiffness: float = 100.0  # N/m per leg, vertical: ~0.1 mm sag per leg under a third of 3 g
    leg_damping: float = 0.3  # N s/m per leg: sag settles in ~3 ms (k/c), well inside a swing
    swing_height: float = 0.8e-3  # m, as ModelParams.swing_height
    swing_shape: float = 1.0  # exponent p, as ModelParams.swing_shape
    landing_height_kept: float = 1.0  # as ModelParams.landing_height_kept
    body_mass: float = 3.0e-3  # kg, Table I
    pitch_inertia: float = 3.0e-3 * 0.042**2 / 12 + 2e-7  # body box plus legs, kg m^2
    roll_inertia: float = 3.0e-3 * 0.010**2 / 12 + 3e-8  # body box plus legs, kg m^2
    foot_x: tuple[float, ...] = (12e-3, 12e-3, 0.0, 0.0, -12e-3, -12e-3)  # stance centres
    foot_y: tuple[float, ...] = (-11e-3, 11e-3, -11e-3, 11e-3, -11e-3, 11e-3)  # right = -
    com_x: float = 0.0  # m, centre of mass ahead of the middle feet
    stroke: float = 2e-3  # m, D (paper): stance feet move from +D/2 to -D/2 about foot_x
    swing_duration: float = 34e-3  # s, T_sw (paper)
    scuff_fraction: float = 0.5  # as ModelParams.scuff_fraction
    dt: float = 5e-5  # s; semi-implicit (damping implicit), converged at 2.5e-5 for defaults
    k_contralateral: float = 32.0  # paper
    k_ipsilateral: float = 40.0  # paper


@njit(cache=True)
def _det3(m: np.ndarray) -> float:
    return (
        m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1])
        - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
        + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0])
    )


@njit(cache=True)
def _solve3(a: np.ndarray, b: np.ndarray, x: np.ndarray) -> None:
    """x = a^-1 b for a 3x3 a, by Cramer's rule (numba's linalg would need scipy)."""
    d = _det3(a)
    col = np.empty((3, 3))
    for j in range(3):
        col[:, :] = a
        col[:, j] = b
        x[j] = _det3(col) / d


@njit(cache=True)
def _run(
    beta: float,
    phi_aep: float,
    d31: float,
    duration: float,
    phase_reset: bool,
    num: np.ndarray,
    xs: np.ndarray,
    ys: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    k, c, h, p, kept, mass, ip, ir, comx, tsw, scuff, dt, kc, ki, stroke = num
    omega = phi_aep / tsw
    weight = mass * 9.81
    a = d31 / TWO_PI
    off = np.array([0.0, 0.5, a, a + 0.5, 2.0 * a, 2.0 * a + 0.5])
    phi = np.empty(6)
    stance = np.zeros(6, dtype=np.bool_)
    phi_td = np.zeros(6)
    z_land = np.zeros(6)
    for i in range(6):
        phi[i] = (off[i] * TWO_PI + 3.0) % TWO_PI  # leg 1 mid-stance at the start
        if phi[i] >= phi_aep:
            stance[i] = True
            phi_td[i] = phi_aep
    q = np.zeros(3)  # heave sag, pitch and roll as sag gradients along x and y
    v = np.zeros(3)
    q[0] = weight / (k * max(1, stance.sum()))
    nxt = np.empty(6)
    scratch = np.empty((2, 6))
    lhs = np.empty((3, 3))
    rhs = np.empty(3)
    inertia = np.array([mass, ip, ir])
    t_out = np.full(MAX_EVENTS, np.nan)
    d_out = np.full(MAX_EVENTS, np.nan)
    nout = 0
    share_sum = 0.0  # share of the swing done at each touchdown after the first third
    share_n = 0
    for step in range(int(duration / dt)):
        lhs[:, :] = 0.0
        rhs[0] = weight
        rhs[1] = weight * comx
        rhs[2] = 0.0
        for i in range(6):
            if not stance[i]:
                continue
            span = TWO_PI - phi_td[i]
            frac = 1.0 if span <= 1e-9 else min(max((phi[i] - phi_td[i]) / span, 0.0), 1.0)
            x = xs[i] + stroke * (0.5 - frac)
            g = (1.0, x, ys[i])
            w = q[0] + x * q[1] + ys[i] * q[2]
            wd = v[0] + x * v[1] + ys[i] * v[2]
            rest = kept * z_land[i] * (1.0 - frac)
            rest_rate = 0.0 if span <= 1e-9 else -kept * z_land[i] * omega / span
            if k * (w - rest) + c * (wd - rest_rate) <= 0.0:
                continue  # a foot cannot pull
            f_spring = k * (w - rest) - c * rest_rate
            for m in range(3):
                rhs[m] -= f_spring * g[m]
                for n in range(3):
                    lhs[m, n] += dt * c * g[m] * g[n]  # damping taken implicitly
        for m in range(3):
            lhs[m, m] += inertia[m]
            rhs[m] = inertia[m] * v[m] + dt * rhs[m]
        _solve3(lhs, rhs, v)
        for m in range(3):
            q[m] += dt * v[m]
        advance_phases(phi, omega, kc, ki, 0.0, 0.0, dt, nxt, scratch)
        for i in range(6):
            pn = nxt[i]
            if stance[i]:
                if pn >= TWO_PI:
                    stance[i] = False
                    pn -= TWO_PI
            else:
                ph = pn - TWO_PI if pn >= TWO_PI else pn
                w = q[0] + (xs[i] + 0.5 * stroke) * q[1] + ys[i] * q[2]  # lands near the AEP
                zf = 0.0
                if ph < phi_aep:
                    zf = h * math.sin(math.pi * (max(ph, 0.0) / phi_aep) ** p)
                if ph >= scuff * phi_aep and zf - w <= 0.0:
                    stance[i] = True
                    if step * dt > duration / 3.0:
                        share_sum += ph / phi_aep
                        share_n += 1
                    phi_td[i] = phi_aep if phase_reset else ph
                    z_land[i] = zf
                    pn = phi_td[i]
                    if i == 0 and nout < MAX_EVENTS:
                        t_out[nout] = step * dt
                        d_out[nout] = (phi[2] - phi[0]) % TWO_PI
                        nout += 1
                elif pn >= TWO_PI:
                    pn -= TWO_PI  # missed step
            nxt[i] = pn
        phi[:] = nxt
    share = share_sum / share_n if share_n > 0 else np.nan
    return t_out[:nout], d_out[:nout], q, share


@dataclass(frozen=True)
class ReducedRun:
    """Leg-1 touchdown times and Delta31 there, and the mean share of the swing done when a
    foot lands (after the first third of the run; 1 = at the AEP, as `gait.landing_share`)."""

    times: np.ndarray
    d31: np.ndarray
    landing_share: float


def run_reduced(
    beta: float,
    d31_init: float,
    *,
    duration_s: float = 6.0,
    params: ReducedParams | None = None,
    phase_reset: bool = True,
) -> ReducedRun:
    """One run; raises FloatingPointError if the body state blew up (the reduced body fell)."""
    r = params or ReducedParams()
    num = np.array([r.leg_stiffness, r.leg_damping, r.swing_height, r.swing_shape,
                    r.landing_height_kept, r.body_mass, r.pitch_inertia, r.roll_inertia, r.com_x,
                    r.swing_duration, r.scuff_fraction, r.dt, r.k_contralateral,
                    r.k_ipsilateral, r.stroke])  # fmt: skip
    t, d, q, share = _run(beta, phi_aep(beta), d31_init, duration_s, phase_reset, num,
                          np.array(r.foot_x), np.array(r.foot_y))  # fmt: skip
    if not np.all(np.isfinite(q)) or abs(q[0]) > 1e-2:
        raise FloatingPointError(f"reduced model diverged (beta {beta}, Delta31 {d31_init})")
    return ReducedRun(times=t, d31=d, landing_share=float(share))


def simulate_reduced(
    beta: float,
    d31_init: float,
    *,
    duration_s: float = 6.0,
    params: ReducedParams | None = None,
    phase_reset: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """(times of leg-1 touchdowns, Delta31 there); raises if the body state blew up."""
    run = run_reduced(beta, d31_init, duration_s=duration_s, params=params, phase_reset=phase_reset)
    return run.times, run.d31


def attractors(
    beta: float,
    *,
    n_init: int = 12,
    duration_s: float = 6.0,
    params: ReducedParams | None = None,
) -> list[float]:
    """Final Delta31 from n_init starts spread over the circle (off the symmetric points)."""
    return [
        float(simulate_reduced(beta, float(x), duration_s=duration_s, params=params)[1][-1])
        for x in initial_values(n_init)
    ]

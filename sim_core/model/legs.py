"""Leg tip trajectories as functions of the oscillator phase, and inverse kinematics (Fig. 3).

Phase convention (paper): phi = 0 at the PEP, phi = phi_AEP = 2 pi (1 - beta) at the AEP.

- Swing, phi in [0, phi_AEP): the upper arc of a closed curve from the PEP to the AEP,
  s = phi / phi_AEP, x = PEP + D (1 - cos(pi s)) / 2, z = line + h sin(pi s^p).
- Swing that has not touched down by the AEP: the closed curve continues along its lower side,
  the AEP-PEP line, at the stance speed; reaching the PEP without touchdown starts a new swing.
  With `late_swing_descent` q > 0 it also keeps descending below the line at q times the
  curve's final descent speed (h pi p per unit s), reaching for the ground (the other
  reading of "until the leg touches the ground").
- Stance: a straight line from the landing position LP (the commanded tip position at the
  detected touchdown) to the PEP, covered as phi goes from its value at touchdown to 2 pi.

Everything here is scalar code compiled with numba, called per leg from the controller kernel;
the geometry arrives packed in one float array (`pack_geometry`) so that kernels take few args.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from sim_core.model.anatomy import LEG_SIDE, attachment_points, stance_line
from sim_core.model.gait import TWO_PI
from sim_core.model.params import ModelParams

# layout of the packed geometry array
G_AEP = 0  # (6, 3) AEP in body frame, flattened: 18 values
G_PEP = 18  # (6, 3) PEP
G_ATTACH = 36  # (6, 3) attachment points
G_SIDE = 54  # (6,) +1 left, -1 right
G_LC = 60
G_LF = 61
G_LT = 62
G_HSW = 63
G_SHAPE = 64
G_LPZ = 65  # share of the landing height kept by the stance line
G_DESC = 66  # descent below the line past the AEP, m per unit of s = phi / phi_AEP
G_LEVEL = 67  # 1: trajectories in the level frame of the body's heading, 0: in the body frame
G_SIZE = 68


def pack_geometry(p: ModelParams) -> np.ndarray:
    aep, pep = stance_line(p)
    g = np.zeros(G_SIZE)
    g[G_AEP : G_AEP + 18] = aep.ravel()
    g[G_PEP : G_PEP + 18] = pep.ravel()
    g[G_ATTACH : G_ATTACH + 18] = attachment_points(p).ravel()
    g[G_SIDE : G_SIDE + 6] = LEG_SIDE
    g[G_LC] = p.coxa_length
    g[G_LF] = p.femur_length
    g[G_LT] = p.tibia_length
    g[G_HSW] = p.swing_height
    g[G_SHAPE] = p.swing_shape
    g[G_LPZ] = p.landing_height_kept
    g[G_DESC] = p.late_swing_descent * p.swing_height * math.pi * p.swing_shape
    g[G_LEVEL] = 1.0 if p.trajectory_frame == "level" else 0.0
    return g


@njit(cache=True)
def tilt_matrix(quat: np.ndarray, out: np.ndarray) -> None:
    """The body's tilt without its heading, R_tilt = R_z(-yaw) R for the body's rotation R
    (body -> ground frame, from its unit quaternion w, x, y, z): a vector v given in the level
    frame of the body's heading is R_tilt^T v in the body frame (`to_body`)."""
    w, x, y, z = quat[0], quat[1], quat[2], quat[3]
    r00 = 1.0 - 2.0 * (y * y + z * z)
    r01 = 2.0 * (x * y - w * z)
    r02 = 2.0 * (x * z + w * y)
    r10 = 2.0 * (x * y + w * z)
    r11 = 1.0 - 2.0 * (x * x + z * z)
    r12 = 2.0 * (y * z - w * x)
    yaw = math.atan2(r10, r00)
    c = math.cos(yaw)
    s = math.sin(yaw)
    out[0, 0] = c * r00 + s * r10
    out[0, 1] = c * r01 + s * r11
    out[0, 2] = c * r02 + s * r12
    out[1, 0] = -s * r00 + c * r10
    out[1, 1] = -s * r01 + c * r11
    out[1, 2] = -s * r02 + c * r12
    out[2, 0] = 2.0 * (x * z - w * y)
    out[2, 1] = 2.0 * (y * z + w * x)
    out[2, 2] = 1.0 - 2.0 * (x * x + y * y)


@njit(cache=True)
def to_body(tilt: np.ndarray, v: np.ndarray) -> None:
    """Rewrite v (a vector in the level frame of the heading) in the body frame, in place:
    v <- R_tilt^T v."""
    a = tilt[0, 0] * v[0] + tilt[1, 0] * v[1] + tilt[2, 0] * v[2]
    b = tilt[0, 1] * v[0] + tilt[1, 1] * v[1] + tilt[2, 1] * v[2]
    c = tilt[0, 2] * v[0] + tilt[1, 2] * v[1] + tilt[2, 2] * v[2]
    v[0] = a
    v[1] = b
    v[2] = c


@njit(cache=True)
def swing_point(geo: np.ndarray, leg: int, phi: float, phi_aep: float, out: np.ndarray) -> None:
    """Tip target on the closed swing curve at phase phi (no touchdown yet)."""
    a = G_AEP + 3 * leg
    b = G_PEP + 3 * leg
    d = geo[a] - geo[b]
    if phi < phi_aep:
        # coupling can briefly run a phase backwards past 0: hold the tip at the PEP then
        # (a negative s would also make s**p undefined)
        s = max(phi, 0.0) / phi_aep
        out[0] = geo[b] + d * 0.5 * (1.0 - math.cos(math.pi * s))
        out[1] = geo[b + 1]
        out[2] = geo[b + 2] + geo[G_HSW] * math.sin(math.pi * s ** geo[G_SHAPE])
    else:
        f = (phi - phi_aep) / (TWO_PI - phi_aep)
        out[0] = geo[a] - d * min(f, 1.0)
        out[1] = geo[a + 1]
        out[2] = geo[a + 2] - geo[G_DESC] * ((phi - phi_aep) / phi_aep)


@njit(cache=True)
def stance_point(
    geo: np.ndarray, leg: int, phi: float, phi_td: float, lp: np.ndarray, out: np.ndarray
) -> None:
    """Tip target on the straight line LP -> PEP; phi runs from phi_td (at LP) to 2 pi (PEP)."""
    b = G_PEP + 3 * leg
    span = TWO_PI - phi_td
    f = 1.0 if span <= 1e-9 else (phi - phi_td) / span
    f = min(max(f, 0.0), 1.0)
    for k in range(3):
        out[k] = lp[k] + (geo[b + k] - lp[k]) * f


@njit(cache=True)
def inverse_kinematics(geo: np.ndarray, leg: int, tip: np.ndarray, q: np.ndarray) -> bool:
    """Joint angles (q1 yaw, q2, q3) that put the tip at `tip` (body frame).

    Knee-up solution (femur raised, tibia down), as an insect stands. Returns False when the
    target is out of reach; the angles then point at it as far as the leg goes.
    """
    c = G_ATTACH + 3 * leg
    fwd = tip[0] - geo[c]
    out_ = geo[G_SIDE + leg] * tip[1] - geo[c + 1] * geo[G_SIDE + leg]
    up = tip[2] - geo[c + 2]
    q[0] = math.atan2(fwd, out_)
    r = math.sqrt(fwd * fwd + out_ * out_) - geo[G_LC]
    l2 = geo[G_LF]
    l3 = geo[G_LT]
    c3 = (r * r + up * up - l2 * l2 - l3 * l3) / (2.0 * l2 * l3)
    ok = -1.0 <= c3 <= 1.0
    c3 = min(max(c3, -1.0), 1.0)
    q[2] = -math.acos(c3)
    q[1] = math.atan2(up, r) - math.atan2(l3 * math.sin(q[2]), l2 + l3 * math.cos(q[2]))
    return ok


@njit(cache=True)
def forward_kinematics(geo: np.ndarray, leg: int, q: np.ndarray, tip: np.ndarray) -> None:
    """Tip position (body frame) for joint angles q; the inverse of `inverse_kinematics`."""
    c = G_ATTACH + 3 * leg
    side = geo[G_SIDE + leg]
    l2 = geo[G_LF]
    l3 = geo[G_LT]
    r = geo[G_LC] + l2 * math.cos(q[1]) + l3 * math.cos(q[1] + q[2])
    up = l2 * math.sin(q[1]) + l3 * math.sin(q[1] + q[2])
    tip[0] = geo[c] + r * math.sin(q[0])
    tip[1] = geo[c + 1] + side * r * math.cos(q[0])
    tip[2] = geo[c + 2] + up

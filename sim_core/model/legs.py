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
the geometry arrives as one named structure (`LegGeometry`, a NamedTuple numba compiles like a
struct) so that kernels take one argument and read each quantity by its name.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from sim_core.model.anatomy import LEG_SIDE, attachment_points, stance_line
from sim_core.model.gait import TWO_PI
from sim_core.model.params import ModelParams


class LegGeometry(NamedTuple):
    """What the leg kernels read of the model (lengths in m, body frame, paper leg order)."""

    aep: np.ndarray  # (6, 3) anterior extreme positions
    pep: np.ndarray  # (6, 3) posterior extreme positions
    attach: np.ndarray  # (6, 3) coxa attachment points
    side: np.ndarray  # (6,) +1 left, -1 right
    coxa: float
    femur: float
    tibia: float
    swing_height: float
    swing_shape: float
    landing_kept: float  # share of the landing height kept by the stance line
    descent: float  # below the line past the AEP, m per unit of s = phi / phi_AEP
    level: bool  # trajectories in the level frame of the body's heading (else the body frame)


def leg_geometry(p: ModelParams) -> LegGeometry:
    aep, pep = stance_line(p)

    def rows(a: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(a, dtype=np.float64).reshape(6, 3)

    return LegGeometry(
        aep=rows(aep),
        pep=rows(pep),
        attach=rows(attachment_points(p)),
        side=np.ascontiguousarray(LEG_SIDE, dtype=np.float64),
        coxa=float(p.legs.coxa_length),
        femur=float(p.legs.femur_length),
        tibia=float(p.legs.tibia_length),
        swing_height=float(p.trajectory.swing_height),
        swing_shape=float(p.trajectory.swing_shape),
        landing_kept=float(p.trajectory.landing_height_kept),
        descent=float(
            p.trajectory.late_swing_descent
            * p.trajectory.swing_height
            * math.pi
            * p.trajectory.swing_shape
        ),
        level=p.trajectory.trajectory_frame == "level",
    )


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
def swing_point(geo: LegGeometry, leg: int, phi: float, phi_aep: float, out: np.ndarray) -> None:
    """Tip target on the closed swing curve at phase phi (no touchdown yet)."""
    a = geo.aep
    b = geo.pep
    d = a[leg, 0] - b[leg, 0]
    if phi < phi_aep:
        # coupling can briefly run a phase backwards past 0: hold the tip at the PEP then
        # (a negative s would also make s**p undefined)
        s = max(phi, 0.0) / phi_aep
        out[0] = b[leg, 0] + d * 0.5 * (1.0 - math.cos(math.pi * s))
        out[1] = b[leg, 1]
        out[2] = b[leg, 2] + geo.swing_height * math.sin(math.pi * s**geo.swing_shape)
    else:
        f = (phi - phi_aep) / (TWO_PI - phi_aep)
        out[0] = a[leg, 0] - d * min(f, 1.0)
        out[1] = a[leg, 1]
        out[2] = a[leg, 2] - geo.descent * ((phi - phi_aep) / phi_aep)


@njit(cache=True)
def stance_point(
    geo: LegGeometry, leg: int, phi: float, phi_td: float, lp: np.ndarray, out: np.ndarray
) -> None:
    """Tip target on the straight line LP -> PEP; phi runs from phi_td (at LP) to 2 pi (PEP)."""
    b = geo.pep
    span = TWO_PI - phi_td
    f = 1.0 if span <= 1e-9 else (phi - phi_td) / span
    f = min(max(f, 0.0), 1.0)
    for k in range(3):
        out[k] = lp[k] + (b[leg, k] - lp[k]) * f


@njit(cache=True)
def inverse_kinematics(geo: LegGeometry, leg: int, tip: np.ndarray, q: np.ndarray) -> bool:
    """Joint angles (q1 yaw, q2, q3) that put the tip at `tip` (body frame).

    Knee-up solution (femur raised, tibia down), as an insect stands. Returns False when the
    target is out of reach; the angles then point at it as far as the leg goes.
    """
    c = geo.attach
    side = geo.side[leg]
    fwd = tip[0] - c[leg, 0]
    out_ = side * tip[1] - c[leg, 1] * side
    up = tip[2] - c[leg, 2]
    q[0] = math.atan2(fwd, out_)
    r = math.sqrt(fwd * fwd + out_ * out_) - geo.coxa
    l2 = geo.femur
    l3 = geo.tibia
    c3 = (r * r + up * up - l2 * l2 - l3 * l3) / (2.0 * l2 * l3)
    ok = -1.0 <= c3 <= 1.0
    c3 = min(max(c3, -1.0), 1.0)
    q[2] = -math.acos(c3)
    q[1] = math.atan2(up, r) - math.atan2(l3 * math.sin(q[2]), l2 + l3 * math.cos(q[2]))
    return ok


@njit(cache=True)
def forward_kinematics(geo: LegGeometry, leg: int, q: np.ndarray, tip: np.ndarray) -> None:
    """Tip position (body frame) for joint angles q; the inverse of `inverse_kinematics`."""
    c = geo.attach
    side = geo.side[leg]
    l2 = geo.femur
    l3 = geo.tibia
    r = geo.coxa + l2 * math.cos(q[1]) + l3 * math.cos(q[1] + q[2])
    up = l2 * math.sin(q[1]) + l3 * math.sin(q[1] + q[2])
    tip[0] = c[leg, 0] + r * math.sin(q[0])
    tip[1] = c[leg, 1] + side * r * math.cos(q[0])
    tip[2] = c[leg, 2] + up

"""Where the legs are: names, sides, pairs, coxa attachment points and the stance line.

The one place both the MuJoCo builder (`mjspec`) and the leg kinematics (`legs`) read the
hexapod's layout from, so that neither imports the other for it.
"""

from __future__ import annotations

import numpy as np

from sim_core.model.params import ModelParams

LEG_NAMES: tuple[str, ...] = ("R1", "L1", "R2", "L2", "R3", "L3")
"""Paper order: legs 1, 2 fore (right, left); 3, 4 middle; 5, 6 hind."""

# +1 for left legs (y > 0), -1 for right legs
LEG_SIDE = np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0])
# leg pair of each leg: 0 fore, 1 middle, 2 hind
LEG_PAIR = np.array([0, 0, 1, 1, 2, 2])


def leg_names() -> tuple[str, ...]:
    return LEG_NAMES


def attachment_points(p: ModelParams) -> np.ndarray:
    """(6, 3) coxa attachment points in the body frame."""
    xs = np.array([p.legs.attach_x_fore, p.legs.attach_x_mid, p.legs.attach_x_hind])[LEG_PAIR]
    return np.stack([xs, LEG_SIDE * p.legs.attach_y, np.full(6, p.legs.attach_z)], axis=1)


def stance_line(p: ModelParams) -> tuple[np.ndarray, np.ndarray]:
    """(AEP, PEP), each (6, 3), in the body frame: the tip's nominal stance segment."""
    cx = np.array(
        [p.trajectory.stance_x_fore, p.trajectory.stance_x_mid, p.trajectory.stance_x_hind]
    )[LEG_PAIR]
    y = LEG_SIDE * p.trajectory.foot_y
    z = np.full(6, p.legs.attach_z - p.trajectory.stand_height)
    aep = np.stack([cx + p.trajectory.stroke / 2, y, z], axis=1)
    pep = np.stack([cx - p.trajectory.stroke / 2, y, z], axis=1)
    return aep, pep


def leg_reach(p: ModelParams) -> float:
    """m: the farthest a foot's surface can be from its coxa attachment (coxa + femur + tibia,
    the sprung tarsus' extension, the foot sphere): a body whose lowest attachment is higher
    above the floor than this has no foot that can touch it."""
    return (
        p.legs.coxa_length
        + p.legs.femur_length
        + p.legs.tibia_length
        + p.legs.tarsus_extension
        + p.legs.foot_radius
    )

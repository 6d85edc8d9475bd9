"""Build the hexapod as an MjModel with MjSpec: one rigid body, six 3-link legs, a floor.

Frames. Body frame: x forward, y left, z up, origin at the centre of the body box. Each leg root
frame sits at the coxa attachment with its local x pointing outward; joint 1 turns the leg about
the vertical so that a positive angle moves the tip forward on both sides, joints 2 and 3 turn about
the horizontal axis normal to the leg plane so that positive angles raise the femur/tibia.

Slope. The floor stays flat and gravity is tilted instead: a slope of theta (uphill +) walking
along +x is the same physics as gravity (-g sin theta, 0, -g cos theta). It can then change
during a run (Fig. 9b) without rebuilding the model, and per simulation in a batch.

Only feet touch the floor, as the paper models leg-tip contact only; how they touch it (MuJoCo's
contact constraint or the paper's viscoelastic elements) is the ground's (ground.py), which adds
itself to the spec.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from sim_core.model import ground
from sim_core.model.anatomy import LEG_NAMES, LEG_PAIR, LEG_SIDE, attachment_points, stance_line
from sim_core.model.legs import inverse_kinematics, leg_geometry
from sim_core.model.params import ModelParams

GRAVITY = 9.81

_INTEGRATOR = {
    "euler": mujoco.mjtIntegrator.mjINT_EULER,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "rk4": mujoco.mjtIntegrator.mjINT_RK4,
    "discrete": mujoco.mjtIntegrator.mjINT_DISCRETE,
}


def integrator_enum(name: str) -> int:
    try:
        return int(_INTEGRATOR[name])
    except KeyError:
        raise ValueError(
            f"unknown integrator {name!r}; choose from {sorted(_INTEGRATOR)}"
        ) from None


def gravity_vector(slope_deg: float) -> np.ndarray:
    """Gravity in the floor frame for a slope of slope_deg (uphill positive along +x)."""
    th = math.radians(slope_deg)
    return np.array([-GRAVITY * math.sin(th), 0.0, -GRAVITY * math.cos(th)])


def box_inertia(mass: float, size: tuple[float, float, float]) -> np.ndarray:
    """Principal inertia of a solid box with full side lengths `size`."""
    a, b, c = size
    return mass / 12.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])


def _capsule_inertia(mass: float, length: float, radius: float) -> np.ndarray:
    """Principal inertia (about its centre) of a thin rod along x; the radius term bounds it."""
    axial = 0.5 * mass * radius * radius
    transverse = mass * (length * length / 12.0 + radius * radius / 4.0)
    return np.array([axial, transverse, transverse])


SOLVERS = {"newton": mujoco.mjtSolver.mjSOL_NEWTON, "cg": mujoco.mjtSolver.mjSOL_CG,
           "pgs": mujoco.mjtSolver.mjSOL_PGS}  # fmt: skip
CONES = {"elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC, "pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL}


def build_spec(p: ModelParams, slope_deg: float = 0.0, visual: bool = True) -> mujoco.MjSpec:
    """The hexapod's spec. visual=False leaves out what only drawing needs (the body box, the
    leg capsules, the light): their masses are zero and inertias explicit, so the dynamics are
    the same, and MuJoCo stops placing 19 geoms every step (~5% of a step)."""
    spec = mujoco.MjSpec()
    spec.modelname = "insect_gait_hexapod"
    opt = spec.option
    opt.timestep = p.numerics.dt
    opt.integrator = integrator_enum(p.numerics.integrator)
    opt.cone = CONES[p.numerics.cone]
    opt.impratio = p.contact.impratio
    opt.noslip_iterations = p.contact.noslip_iterations
    opt.tolerance = p.numerics.solver_tolerance
    opt.solver = SOLVERS[p.numerics.solver]
    opt.iterations = p.numerics.solver_iterations
    if not p.numerics.warmstart:
        opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_WARMSTART)
    opt.gravity = gravity_vector(slope_deg)
    # The hexapod is one constraint island whenever a foot touches, so MuJoCo's island
    # discovery only costs: off, one simulation runs 4-5% faster with bit-identical results.
    opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_ISLAND)

    world = spec.worldbody
    floor = world.add_geom(
        name="floor",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0.5, 0.5, 0.01],
        contype=0,
        conaffinity=1,
        rgba=[0.85, 0.85, 0.8, 1.0],
    )
    floor.friction = [p.contact.friction, p.contact.torsional_friction, p.contact.rolling_friction]
    if visual:
        world.add_light(pos=[0, 0, 1.0], dir=[0, 0, -1])

    torso = world.add_body(
        name="torso",
        pos=[0.0, 0.0, p.trajectory.stand_height - p.legs.attach_z + p.legs.foot_radius],
    )
    torso.add_freejoint(name="root")
    size = (p.body.body_length, p.body.body_width, p.body.body_thickness)
    torso.explicitinertial = True
    torso.mass = p.body.body_mass
    torso.ipos = [p.body.com_offset_x, 0.0, 0.0]
    torso.inertia = box_inertia(p.body.body_mass, size)
    if visual:
        torso.add_geom(
            name="torso_geom",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[s / 2 for s in size],
            contype=0,
            conaffinity=0,
            mass=0.0,
            rgba=[0.45, 0.3, 0.2, 1.0],
        )

    attach = attachment_points(p)
    tarsus_axes = tarsus_axes_in_tibia(p)
    for i, name in enumerate(LEG_NAMES):
        side = LEG_SIDE[i]
        yaw = -math.pi / 2 if side < 0 else math.pi / 2  # local x points outward
        quat = [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]
        coxa = torso.add_body(name=f"{name}_coxa", pos=attach[i].tolist(), quat=quat)
        coxa.add_joint(
            name=f"{name}_j1",
            type=mujoco.mjtJoint.mjJNT_HINGE,
            axis=[0.0, 0.0, -side],  # positive = tip forward on both sides
            armature=p.joints.armature,
        )
        _add_link(
            coxa, f"{name}_coxa", p.legs.coxa_mass, p.legs.coxa_length, p.legs.coxa_radius, visual
        )
        femur = coxa.add_body(name=f"{name}_femur", pos=[p.legs.coxa_length, 0.0, 0.0])
        femur.add_joint(
            name=f"{name}_j2",
            type=mujoco.mjtJoint.mjJNT_HINGE,
            axis=[0.0, -1.0, 0.0],  # positive = raise
            armature=p.joints.armature,
        )
        _add_link(
            femur,
            f"{name}_femur",
            p.legs.femur_mass,
            p.legs.femur_length,
            p.legs.femur_radius,
            visual,
        )
        tibia = femur.add_body(name=f"{name}_tibia", pos=[p.legs.femur_length, 0.0, 0.0])
        tibia.add_joint(
            name=f"{name}_j3",
            type=mujoco.mjtJoint.mjJNT_HINGE,
            axis=[0.0, -1.0, 0.0],
            armature=p.joints.armature,
        )
        _add_link(
            tibia,
            f"{name}_tibia",
            p.legs.tibia_mass,
            p.legs.tibia_length,
            p.legs.tibia_radius,
            visual,
        )
        tip_body, tip_pos = tibia, [p.legs.tibia_length, 0.0, 0.0]
        if p.legs.tarsus_stiffness > 0:  # a sprung tarsus: the foot slides along the tibia axis
            tip_body = tibia.add_body(name=f"{name}_tarsus", pos=tip_pos)
            tip_body.explicitinertial = True
            tip_body.mass = p.legs.tarsus_mass
            tip_body.inertia = [p.legs.tarsus_inertia] * 3
            tip_body.add_joint(
                name=f"{name}_tarsus",
                type=mujoco.mjtJoint.mjJNT_SLIDE,
                axis=tarsus_axes[i].tolist(),  # positive = compressed (the foot moves up)
                stiffness=p.legs.tarsus_stiffness,
                damping=p.legs.tarsus_damping,
                range=[-p.legs.tarsus_extension, p.legs.tarsus_compression],
                limited=mujoco.mjtLimited.mjLIMITED_TRUE,
            )
            tip_pos = [0.0, 0.0, 0.0]
        tip_body.add_geom(  # how it touches the floor is the ground's (add_to below)
            name=ground.foot_geom(name),
            type=mujoco.mjtGeom.mjGEOM_SPHERE,
            size=[p.legs.foot_radius, 0, 0],
            pos=tip_pos,
            contype=0,
            conaffinity=0,
            mass=0.0,
            rgba=[0.1, 0.1, 0.1, 1.0],
        )
        tip_body.add_site(  # the foot's centre: its height is the touch sense (controller.py)
            name=ground.foot_site(name),
            type=mujoco.mjtGeom.mjGEOM_SPHERE,
            size=[p.legs.foot_radius * 1.01, 0, 0],
            pos=tip_pos,
        )

    # One actuator per joint makes tau = kp (q* - q) + kd (dq*/dt - dq/dt) with q* ramping
    # linearly inside each control period, computed by MuJoCo itself: integrator dynamics,
    # act' = ctrl = dq*/dt, and force = kp act - kp q - kd qdot (the damping part implicit in
    # the implicit integrators). The controller writes act = q*(t0) + (kd/kp) dq*/dt, which
    # folds the feed-forward kd dq*/dt into the set-point (exact: dq*/dt is constant over the
    # period), and ctrl = dq*/dt, once per period (`servo_leads` gives kd/kp per joint).
    for leg, name in enumerate(LEG_NAMES):
        for j in ("j1", "j2", "j3"):
            kp, kd = joint_gains(p, j, int(LEG_PAIR[leg]))
            act = spec.add_actuator(name=f"{name}_{j}_pd", target=f"{name}_{j}")
            act.trntype = mujoco.mjtTrn.mjTRN_JOINT
            act.dyntype = mujoco.mjtDyn.mjDYN_INTEGRATOR
            act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
            act.gainprm[0] = kp
            act.biastype = mujoco.mjtBias.mjBIAS_AFFINE
            act.biasprm[0] = 0.0
            act.biasprm[1] = -kp
            act.biasprm[2] = -kd
    ground.ground_for(p).add_to(spec)  # the feet's contact: constraint or penalty
    return spec


def lift_scale(p: ModelParams, pair: int) -> float:
    """How much the lift joints of leg pair `pair` (0 fore, 1 middle, 2 hind) are scaled so
    that the middle pair is `support_ratio` times as stiff as fore and hind, at equal total."""
    r = p.joints.support_ratio
    return 3.0 * (r if pair == 1 else 1.0) / (2.0 + r)


def joint_gains(p: ModelParams, joint: str, pair: int = 0) -> tuple[float, float]:
    """(kp, kd) of leg joint "j1" (yaw), "j2" or "j3" (lift) of a leg of pair `pair`."""
    if joint == "j1":
        return p.joints.kp_yaw, p.joints.kd_yaw
    k = lift_scale(p, pair)  # scales kp and kd alike: the joint's time constant is kept
    return p.joints.kp_lift * k, p.joints.kd_lift * k


def servo_leads(p: ModelParams) -> np.ndarray:
    """(18,) s kd/kp of each leg joint (paper leg order, joints 1-3): how far ahead along the
    desired trajectory the set-point sits so that kp (act - q) carries the feed-forward
    s kd dq*/dt, s the joint group's `velocity_feedforward_*` share (0: tau = kp (q* - q) -
    kd dq/dt, damping on the joint's own velocity)."""
    share = {"j1": p.joints.velocity_feedforward_yaw, "j2": p.joints.velocity_feedforward_lift,
             "j3": p.joints.velocity_feedforward_lift}  # fmt: skip
    per_joint = [share[j] * kd / kp for j, (kp, kd) in ((j, joint_gains(p, j)) for j in share)]
    return np.tile(per_joint, len(LEG_NAMES))


def tarsus_axes_in_tibia(p: ModelParams) -> np.ndarray:
    """(6, 3) slide axes of the sprung tarsi in their tibia frames, pointing 'compressed'.

    'tibia': toward the knee, along the tibia. 'vertical': the body's up direction when the
    leg stands at mid-stance, so the spring carries the load the way a viscoelastic ground
    does (joint 1 turns about the vertical, so only the tibia's pitch q2 + q3 matters).
    """
    if p.legs.tarsus_axis == "tibia":
        return np.tile([-1.0, 0.0, 0.0], (6, 1))
    pitch = mid_stance_angles(p)[:, 1:].sum(axis=1)  # tibia above the horizontal, about -y
    return np.stack([np.sin(pitch), np.zeros(6), np.cos(pitch)], axis=1)


def mid_stance_angles(p: ModelParams) -> np.ndarray:
    """(6, 3) joint angles (q1, q2, q3) with every tip at the middle of its stance line."""
    geo = leg_geometry(p)
    aep, pep = stance_line(p)
    q = np.zeros((6, 3))
    for leg in range(6):
        inverse_kinematics(geo, leg, (aep[leg] + pep[leg]) / 2, q[leg])
    return q


def _add_link(
    body: mujoco.MjsBody, name: str, mass: float, length: float, radius: float, visual: bool
) -> None:
    # inertia is explicit so that the paper's link masses hold exactly, whatever the drawn shape
    body.explicitinertial = True
    body.mass = mass
    body.ipos = [length / 2, 0.0, 0.0]
    body.inertia = _capsule_inertia(mass, length, radius)
    if not visual:
        return
    body.add_geom(
        name=f"{name}_geom",
        type=mujoco.mjtGeom.mjGEOM_CAPSULE,
        fromto=[0.0, 0.0, 0.0, length, 0.0, 0.0],
        size=[radius, 0, 0],
        contype=0,
        conaffinity=0,
        mass=0.0,
        rgba=[0.55, 0.4, 0.25, 1.0],
    )


def leg_qpos_addresses(model: mujoco.MjModel) -> np.ndarray:
    """qpos index of each leg joint (paper leg order, joints 1-3), whatever else is in qpos."""
    return np.array([model.jnt_qposadr[model.joint(f"{n}_{j}").id]
                     for n in LEG_NAMES for j in ("j1", "j2", "j3")])  # fmt: skip


def build_model(
    params: ModelParams | None = None, slope_deg: float = 0.0, visual: bool = True
) -> mujoco.MjModel:
    """Compile the hexapod; `params.dt`/`params.integrator` set the physics options. The
    simulation runs visual=False; drawing uses visual=True with the same bodies and joints, so
    a state (qpos) of one is a state of the other."""
    p = params or ModelParams()
    return build_spec(p, slope_deg, visual).compile()

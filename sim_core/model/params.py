"""Every parameter of the model in one place: the paper's values and the ones we invented.

Fujiki et al. (2013) give Table I (masses and lengths), D, T_sw, the oscillator gains and the
resetting rule. Everything else a simulation needs (where legs attach, how high the body stands,
joint gains, the swing curve, the ground) is ours; each such field says so in its description,
with a one-line reason. `docs/MODEL.md` lists the same table (a test keeps them in sync).

Units are SI inside the core (m, kg, s, rad, N); edge-facing names carry units in their names.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal, NamedTuple, TypeAlias, get_args

from pydantic import BaseModel, ConfigDict, Field, model_validator

Integrator = Literal["euler", "implicit", "implicitfast", "rk4", "discrete"]
# the grounds a walk can stand on (`Contact.ground`): the CLI's and the API's choices read these
Ground = Literal["constraint", "penalty"]
GROUNDS: tuple[Ground, ...] = get_args(Ground)
INTEGRATORS: tuple[Integrator, ...] = ("euler", "implicit", "implicitfast", "rk4", "discrete")
# The largest timestep at which each integrator keeps this model upright, measured: the
# docs/NUMERICS.md grid (3 s runs, beta 0.62 and 0.70) and 0.5 s runs at beta 0.66: euler is
# unstable (MuJoCo BADQACC) at 2e-5 s, rk4 flips at 2.5e-5 s, implicit and implicitfast flip
# at 1e-3 s in the grid (and within 0.15 s at 2e-3 s), discrete runs at 1e-3 s (inaccurately).
# The explicit integrators need small steps because the insect-scale links are tiny and
# strongly damped. The edges (CLI `run`, REST API) refuse larger steps with `step_problem`;
# `RunSpec` itself accepts them, because the numerics studies must be able to show the failure.
MAX_STABLE_DT_S: dict[Integrator, float] = {
    "euler": 1e-5,
    "implicit": 5e-4,
    "implicitfast": 5e-4,
    "rk4": 2e-5,
    "discrete": 1e-3,
}


def step_problem(integrator: str, dt_s: float, *, given: bool = True) -> str | None:
    """Why `dt_s` cannot be stable with `integrator`, in the words the CLI and the API both
    print, or None when it can. `given` False: dt_s is the default, not the user's number."""
    limit = MAX_STABLE_DT_S[integrator]  # type: ignore[index]
    if dt_s <= limit * (1 + 1e-9):
        return None
    shown = f"{dt_s:g}" if given else f"null, i.e. the default {dt_s:g}"
    return (
        f"dt_s ({shown} s) cannot be stable with integrator {integrator}: it needs "
        f"dt_s <= {limit:g} s (measured; see docs/NUMERICS.md)"
    )


PAPER = "paper"
INVENTED = "invented"


# A parameter's provenance, as field metadata (`parameter_table` and the API read it): taken
# from the paper, or invented here with its reason in the description.
FROM_PAPER: dict[str, Any] = {"origin": PAPER}
OURS: dict[str, Any] = {"origin": INVENTED}


def _paper(default: float, reason: str, **bounds: Any) -> float:
    field: float = Field(default, description=reason, json_schema_extra=FROM_PAPER, **bounds)
    return field


def _ours(default: float, reason: str, **bounds: Any) -> float:
    field: float = Field(default, description=reason, json_schema_extra=OURS, **bounds)
    return field


class Body(BaseModel):
    """The body: Table I and the shape the paper leaves open."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    body_mass: float = _paper(3.0e-3, "Table I body mass 3.0 g", gt=0)
    body_length: float = _paper(4.2e-2, "Table I body length 4.2 cm", gt=0)
    body_width: float = _paper(1.0e-2, "Table I body width 1.0 cm", gt=0)
    body_thickness: float = _ours(
        4.0e-3, "box height for inertia and drawing; an insect thorax is a few mm thick", gt=0
    )
    com_offset_x: float = _ours(
        1.0e-3,
        "body centre of mass ahead (+) of the box centre, m: fore/hind load sharing; 1 mm puts "
        "the tripod's fold near the paper's beta 0.67 (docs/studies/gait_campaign3.md)",
        ge=-5e-3,
        le=5e-3,
    )


class Legs(BaseModel):
    """The legs: Table I links, their radii, where they attach, the feet, a sprung tarsus."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    coxa_mass: float = _paper(0.05e-3, "Table I coxa mass 0.05 g", gt=0)
    coxa_length: float = _paper(0.2e-3, "Table I coxa length 0.02 cm", gt=0)
    femur_mass: float = _paper(0.03e-3, "Table I femur mass 0.03 g", gt=0)
    femur_length: float = _paper(2.0e-3, "Table I femur length 0.2 cm", gt=0)
    tibia_mass: float = _paper(0.03e-3, "Table I tibia mass 0.03 g", gt=0)
    tibia_length: float = _paper(1.0e-2, "Table I tibia length 1.0 cm", gt=0)
    coxa_radius: float = _ours(
        0.25e-3, "coxa rod radius, m: the radius term of its inertia (and the drawn capsule)", gt=0
    )
    femur_radius: float = _ours(
        0.3e-3, "femur rod radius, m: a cockroach femur is ~0.5 mm thick", gt=0
    )
    tibia_radius: float = _ours(
        0.15e-3, "tibia rod radius, m: the thin distal segment; bounds its axial inertia", gt=0
    )
    attach_x_fore: float = _ours(
        10e-3, "fore coxa attachment ahead of the box centre; legs sit on the front half", ge=0
    )
    attach_x_mid: float = _ours(0.0, "middle coxa attachment at the box centre")
    attach_x_hind: float = _ours(
        -10e-3, "hind coxa attachment behind the box centre; symmetric with the fore legs", le=0
    )
    attach_y: float = _ours(
        5.0e-3, "coxae attach at the body's side, half of the 1.0 cm width", gt=0
    )
    attach_z: float = _ours(0.0, "coxae attach at the body's mid-height plane")
    foot_radius: float = _ours(0.25e-3, "tarsus tip sphere; small against the 2 mm stroke", gt=0)
    tarsus_stiffness: float = _ours(
        0.0,
        "N/m of a sprung tarsus (slide joint along the tibia at each foot), a physical "
        "viscoelastic foot-ground spring; 0 = rigid foot, no joint (the default)",
        ge=0,
    )
    tarsus_damping: float = _ours(
        0.0, "N s/m of the sprung tarsus; used only when tarsus_stiffness > 0", ge=0
    )
    tarsus_axis: Literal["tibia", "vertical"] = Field(
        "vertical",
        json_schema_extra=OURS,
        description="direction the sprung tarsus slides: 'vertical' (the body's "
        "vertical at mid-stance, as the paper's viscoelastic ground pushes) or 'tibia' (along "
        "the tibia, as in the second study; part of its travel is sideways)",
    )
    tarsus_mass: float = _ours(
        2e-6, "kg of a sprung tarsus: ~7% of a tibia, keeps the spring-mass mode fast", gt=0
    )
    tarsus_inertia: float = _ours(
        1e-13,
        "kg m^2 of a sprung tarsus on each axis: negligible, only keeps MuJoCo's body valid",
        gt=0,
    )
    tarsus_extension: float = _ours(
        5e-4,
        "m a sprung tarsus may extend beyond rest (joint limit): a quarter of the stroke",
        ge=0,
    )
    tarsus_compression: float = _ours(
        1.5e-3, "m a sprung tarsus may compress (joint limit): far beyond its loaded travel", gt=0
    )


class Trajectory(BaseModel):
    """The tips' swing and stance trajectories (Fig. 3): D, T_sw and what the paper leaves."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    stroke: float = _paper(2.0e-3, "D, distance AEP-PEP, 2 mm", gt=0)
    swing_duration: float = _paper(34e-3, "T_sw, swing duration when LP = AEP, 34 ms", gt=0)
    stand_height: float = _ours(
        6.5e-3,
        "height of the coxa attachment above the stance line; keeps the 2+10 mm leg mid-range; "
        "6.5 (not 7) mm makes the tripod die at slow speed first (gait_campaign3.md)",
        gt=0,
    )
    foot_y: float = _ours(
        11.0e-3, "stance line's distance from the midline; sprawled posture of a cockroach", gt=0
    )
    stance_x_fore: float = _ours(
        12e-3, "centre of the fore legs' AEP-PEP segment, 2 mm ahead of their attachment"
    )
    stance_x_mid: float = _ours(0.0, "centre of the middle legs' segment, below the attachment")
    stance_x_hind: float = _ours(
        -12e-3, "centre of the hind legs' segment, 2 mm behind their attachment"
    )
    swing_height: float = _ours(
        0.8e-3, "apex of the swing curve above the AEP-PEP line; clears the ground by ~0.8 mm", gt=0
    )
    swing_shape: float = _ours(
        1.0,
        "exponent p of the lift profile z = h sin(pi s^p); p>1 steepens the descent at the AEP",
        gt=0.2,
        le=5.0,
    )
    landing_height_kept: float = _ours(
        0.0,
        "share of the landing point's height above the AEP-PEP line that the stance line "
        "keeps: 0 = stance runs on the line from LP's fore-aft place (Fig. 3 draws LP on it), "
        "1 = an early landing stays high; 0 lets sag drive the resets (REPRODUCTION.md)",
        ge=0,
        le=1,
    )
    late_swing_descent: float = _ours(
        0.0,
        "a foot still in the air past the AEP descends below the AEP-PEP line at this share of "
        "the swing curve's final descent speed: 0 = it follows the line (our reading of 'until "
        "the leg touches the ground'), 1 = keeps reaching down (the other reading)",
        ge=0,
        le=2,
    )
    trajectory_frame: Literal["body", "level"] = Field(
        "body",
        json_schema_extra=OURS,
        description="frame of the tip trajectories (Fig. 3): 'body' = they pitch and "
        "roll with the body (our reading of 'the line segment between the AEP and the PEP is "
        "parallel to the body'); 'level' = the ground's frame turned to the body's heading, "
        "about each leg's hip (about the body's origin the legs "
        "would give the body no attitude stiffness: it flips within 1 s)",
    )


class Oscillators(BaseModel):
    """The phase oscillators (eqs. 3, 5-7) and the touch sensing that resets them (eq. 4)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    k_contralateral: float = _paper(32.0, "K12=K21=K34=K43=K56=K65, eq. 5", ge=0)
    k_ipsilateral: float = _paper(40.0, "K31=K35=K42=K46, eq. 7", ge=0)
    touch_depth: float = _ours(
        1e-7,
        "foot pressed this far into the ground, m, counts as touch: ~3% of a leg's static "
        "load (2.7 um carries it); a cutaneous threshold, cheaper than MuJoCo's touch sensor",
        gt=0,
    )
    lift_clearance: float = _ours(
        1e-5,
        "a stance foot this far above the ground, m, has left it: counts contact chatter "
        "(RunMeasures.retouches_per_stance); 2x the stance penetration, 0.5% of the stroke",
        gt=0,
    )
    scuff_fraction: float = _ours(
        0.5,
        "touches in swing before s = phi/phi_AEP reaches this are ignored as scuffs",
        ge=0,
        lt=1,
    )


class Joints(BaseModel):
    """Joint control: the PD servos tracking the tip trajectories (the paper leaves them open)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    kp_yaw: float = _ours(5e-3, "joint 1 stiffness, N m/rad: ~0.01 rad sag under stance load", gt=0)
    kp_lift: float = _ours(
        3e-3,
        "joints 2 and 3 stiffness, N m/rad: ~0.15 mm sag under load; this load per unit "
        "stiffness gives the paper's tripod at 2.9-3.0 rad beside the metachronal gait",
        gt=0,
    )
    kd_yaw: float = _ours(
        3e-5, "joint 1 damping, N m s/rad: near critical for the loaded leg", gt=0
    )
    kd_lift: float = _ours(
        3e-6,
        "joints 2, 3 damping, N m s/rad: kd/kp = 1 ms, on the joint velocity (feed-forward "
        "share 0): a lift lag that grows with the sweep speed",
        gt=0,
    )
    support_ratio: float = _ours(
        1.0,
        "lift-joint stiffness (and damping) of the middle pair over fore and hind, at equal "
        "total: r > 2 tips the body about the middle feet (gait-mechanism notes); 1 = equal",
        gt=0,
        le=10,
    )
    velocity_feedforward_yaw: float = _ours(
        1.0,
        "share s of the desired velocity in joint 1's damping, tau = kp (q* - q) + kd (s dq*/dt "
        "- dq/dt): 1 damps the tracking error, 0 the joint velocity (a lag ~ sweep speed)",
        ge=0,
        le=1.5,
    )
    velocity_feedforward_lift: float = _ours(
        0.0,
        "the same share for joints 2 and 3: below 1 a lift joint lags its target in proportion "
        "to the sweep speed, which loads the hind legs more at speed (gait-mechanism notes)",
        ge=0,
        le=1.5,
    )
    armature: float = _ours(
        2e-10,
        "joint rotor inertia, kg m^2, ~ the tibia's own; bounds tiny-link stiffness (as flygym)",
        ge=0,
    )


class _ContactBase(BaseModel):
    """What both grounds set: the floor's friction and MuJoCo's contact options (both grounds'
    models carry them, so both keep them to stay bit-identical)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    friction: float = _ours(1.0, "foot-ground friction; claws and pads grip firmly", gt=0)
    torsional_friction: float = _ours(
        0.005, "MuJoCo's torsional friction of the foot contact (condim 3 leaves it unused)", ge=0
    )
    rolling_friction: float = _ours(
        0.0001, "MuJoCo's rolling friction of the foot contact (condim 3 leaves it unused)", ge=0
    )
    impratio: float = _ours(
        10.0, "elliptic-cone impedance ratio: stops the tiny feet creeping in stance", ge=1
    )
    noslip_iterations: int = Field(
        0,
        json_schema_extra=OURS,
        description="MuJoCo's no-slip solver passes after the main solver "
        "(constraint ground): > 0 removes the soft contact's tangential creep, a candidate "
        "cause of the body turning on slopes; 0 = off, the calibrated default",
        ge=0,
        le=100,
    )


class ConstraintContact(_ContactBase):
    """Today's ground: MuJoCo's soft constraint, its solref and solimp."""

    ground: Literal["constraint"] = Field(
        "constraint",
        json_schema_extra=OURS,
        description="foot-ground contact: 'constraint' = MuJoCo's soft constraint "
        "(solref/solimp below, elliptic cone); 'penalty' = the paper's viscoelastic elements, "
        "normal and tangential spring-dampers per foot anchored at touchdown "
        "(sim_core/model/ground.py, ground_* below)",
    )
    contact_timeconst: float = _ours(
        5e-4, "contact solref time constant, s: stiff 'viscoelastic ground' as in the paper", gt=0
    )
    contact_dampratio: float = _ours(1.0, "contact solref damping ratio: critically damped", gt=0)
    contact_dmin: float = _ours(
        0.9, "solimp d0: contact impedance at zero penetration (MuJoCo's default)", gt=0, lt=1
    )
    contact_dmax: float = _ours(
        0.95,
        "solimp d_width: impedance once pressed in by contact_width (MuJoCo's default)",
        gt=0,
        lt=1,
    )
    contact_width_share: float = _ours(
        0.4, "solimp width as a share of foot_radius: impedance rises over 0.1 mm", gt=0
    )
    contact_midpoint: float = _ours(0.5, "solimp midpoint (MuJoCo's default)", gt=0, lt=1)
    contact_power: float = _ours(2.0, "solimp power (MuJoCo's default)", ge=1)


class PenaltyContact(_ContactBase):
    """The paper's ground: a spring-damper per foot (a compiled MuJoCo engine plugin)."""

    ground: Literal["penalty"] = Field(
        json_schema_extra=OURS,
        description="the paper's viscoelastic elements: normal and tangential spring-dampers "
        "per foot, anchored at touchdown (sim_core/model/ground.py, ground_* below); always "
        "named, so that the cache key and a job's params say which ground",
    )
    ground_stiffness: float = _ours(
        2000.0,
        "N/m normal spring of the penalty ground: the stiffest converged at dt 5e-5 s (5000 "
        "is stable but one start lands elsewhere than at dt/2 and RK4; 2e4 chatters: the spring "
        "is explicit in MuJoCo's integrators); the weight over ~3 feet presses a foot in ~4 um",
        gt=0,
    )
    ground_damping: float = _ours(
        0.1, "N s/m normal damper of the penalty ground: ~0.35 of critical for a 10 mg tip", ge=0
    )
    ground_tangential_stiffness: float = _ours(
        2000.0, "N/m tangential spring from the touchdown point (penalty ground)", gt=0
    )
    ground_tangential_damping: float = _ours(0.1, "N s/m tangential damper (penalty ground)", ge=0)


# The foot-ground contact, one of the two grounds (`ground` names it): a field of the other
# ground is an error, not a number that silently does nothing.
Contact: TypeAlias = Annotated[ConstraintContact | PenaltyContact, Field(discriminator="ground")]


class Numerics(BaseModel):
    """Numerics: integrator, steps, constraint solver, landing instant (docs/NUMERICS.md)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    integrator: Integrator = Field(
        "implicitfast",
        json_schema_extra=OURS,
        description="MuJoCo integrator; treats the PD damping implicitly, cheap",
    )
    dt: float = _ours(
        5e-5, "physics timestep, s; its convergence is measured in docs/NUMERICS.md", gt=0
    )
    control_dt: float = _ours(
        5e-4, "controller update period, s; targets are interpolated per physics step", gt=0
    )
    solver_tolerance: float = _ours(
        1e-6,
        "MuJoCo constraint-solver tolerance; the default 1e-8 costs ~7% more for the same "
        "Delta31 to 1e-4 rad (docs/NUMERICS.md)",
        gt=0,
    )
    solver: Literal["newton", "cg", "pgs"] = Field(
        "newton",
        json_schema_extra=OURS,
        description="MuJoCo's constraint solver (MuJoCo's default); the options "
        "are compared for speed and outcome in `insect-gait numerics --solver-options`",
    )
    solver_iterations: int = Field(
        100,
        json_schema_extra=OURS,
        description="the constraint solver's iteration cap (MuJoCo's default; it "
        "needs ~1-2 per step at the default timestep)",
        ge=1,
        le=1000,
    )
    cone: Literal["elliptic", "pyramidal"] = Field(
        "elliptic",
        json_schema_extra=OURS,
        description="friction cone; elliptic is the physical one (and impratio's "
        "stance grip is calibrated on it)",
    )
    warmstart: bool = Field(
        True,
        json_schema_extra=OURS,
        description="start each step's constraint solve from the last step's forces "
        "(MuJoCo's default)",
    )
    touchdown_interpolation: bool = Field(
        True,
        json_schema_extra=OURS,
        description="landing instant from the interpolated clearance crossing "
        "(True) or at the physics step where the touch is sensed (False); see NUMERICS.md",
    )


class ModelParams(BaseModel):
    """The hexapod, its nervous system and its ground, grouped by concern. Frozen: derive
    variants with `replace`.

    Every parameter has a unique leaf name (`friction`, `kp_lift`), and that name is what the
    edges, the cache key (`leaf_values`) and the studies use: the model takes them flat
    (`ModelParams.of(friction=0.8)`, a job's `params`) as well as grouped, and `replace` and `leaf`
    address them by name. Code reads them through their group (`p.contact.friction`).
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    body: Body = Field(default_factory=Body)
    legs: Legs = Field(default_factory=Legs)
    trajectory: Trajectory = Field(default_factory=Trajectory)
    oscillators: Oscillators = Field(default_factory=Oscillators)
    joints: Joints = Field(default_factory=Joints)
    contact: Contact = Field(default_factory=ConstraintContact)
    numerics: Numerics = Field(default_factory=Numerics)

    @model_validator(mode="before")
    @classmethod
    def _group_leaves(cls, data: Any) -> Any:
        """Leaf names given flat go to their group (a group given as well takes them too)."""
        if not isinstance(data, dict) or not any(k in GROUP_OF for k in data):
            return data
        out: dict[str, Any] = {k: v for k, v in data.items() if k not in GROUP_OF}
        for g, value in list(out.items()):
            if g in GROUPS and isinstance(value, BaseModel):
                out[g] = value.model_dump()
        for leaf, value in data.items():
            if leaf in GROUP_OF:
                into = out.setdefault(GROUP_OF[leaf], {})
                if not isinstance(into, dict):
                    raise ValueError(f"{GROUP_OF[leaf]} is not a group of fields")
                into[leaf] = value
        contact = out.get("contact")
        if isinstance(contact, dict) and "ground" not in contact:
            out["contact"] = {"ground": GROUND_DEFAULT, **contact}  # the union's tag
        return out

    @classmethod
    def of(cls, **leaves: Any) -> ModelParams:
        """Validated parameters from leaf names (`ModelParams.of(ground="penalty")`)."""
        return cls.model_validate(leaves)

    def leaf(self, name: str) -> Any:
        """A parameter's value by its leaf name (`p.leaf("friction")`)."""
        group = getattr(self, GROUP_OF[name])
        if name not in type(group).model_fields:
            raise KeyError(f"{name} is not a parameter of the {self.contact.ground} ground")
        return getattr(group, name)

    def replace(self, **changes: Any) -> ModelParams:
        """A copy with the named leaves changed, unvalidated like `model_copy(update=...)`
        (a study's +-10% may leave a field's range on purpose). A new `ground` starts that
        ground's own constants from their defaults and keeps the shared ones."""
        update: dict[str, dict[str, Any]] = {}
        for name, value in changes.items():
            if name not in GROUP_OF:
                raise KeyError(f"ModelParams has no parameter {name!r}")
            update.setdefault(GROUP_OF[name], {})[name] = value
        groups: dict[str, BaseModel] = {}
        for g, u in update.items():
            group = getattr(self, g)
            tag = u.get("ground", getattr(group, "ground", None))
            if g == "contact" and tag != self.contact.ground:
                shared = {k: getattr(group, k) for k in _ContactBase.model_fields}
                group = CONTACTS[str(tag)].model_validate({"ground": tag} | shared)
            unknown = set(u) - set(type(group).model_fields)
            if unknown:
                raise KeyError(f"{sorted(unknown)}: not parameters of the {tag} ground")
            groups[g] = group.model_copy(update=u)
        return self.model_copy(update=groups)


# each ground's contact model, by its name
CONTACTS: dict[str, type[ConstraintContact] | type[PenaltyContact]] = {
    "constraint": ConstraintContact,
    "penalty": PenaltyContact,
}
# group name -> its models (the contact: one per ground), and leaf name -> its group: the one
# map the flat view reads
GROUPS: dict[str, tuple[type[BaseModel], ...]] = {
    "body": (Body,),
    "legs": (Legs,),
    "trajectory": (Trajectory,),
    "oscillators": (Oscillators,),
    "joints": (Joints,),
    "contact": (ConstraintContact, PenaltyContact),
    "numerics": (Numerics,),
}
GROUP_OF: dict[str, str] = {
    leaf: g for g, models in GROUPS.items() for m in models for leaf in m.model_fields
}
PARAMETER_NAMES: tuple[str, ...] = tuple(GROUP_OF)
GROUND_DEFAULT: Ground = ConstraintContact.model_fields["ground"].default
# the parameters only one ground has (a reading or a lever that sets one means nothing on the
# other ground, where it is refused)
GROUND_ONLY: dict[str, frozenset[str]] = {
    g: frozenset(m.model_fields) - frozenset(_ContactBase.model_fields) - {"ground"}
    for g, m in CONTACTS.items()
}


def leaf_values(model: BaseModel) -> dict[str, Any]:
    """A model's fields that differ from their defaults as {leaf name: JSON value}, a field that
    is itself a model (a group) giving its own leaves by their names; names must be unique.
    The cache key's parameter part: regrouping the fields keeps it."""
    into: dict[str, Any] = {}
    for name, value in model.model_dump(mode="json", exclude_defaults=True).items():
        group = getattr(model, name)
        pairs = leaf_values(group).items() if isinstance(group, BaseModel) else [(name, value)]
        for leaf, v in pairs:
            if leaf in into:
                raise ValueError(f"two parameters are called {leaf!r}: the key needs unique names")
            into[leaf] = v
    return into


def phi_aep(beta: float) -> float:
    """Oscillator phase at the AEP, 2 pi (1 - beta) (Sec. II B 2)."""
    return math.tau * (1.0 - beta)  # math.tau: params imports no sibling module


def omega(beta: float, swing_duration: float) -> float:
    """Basic oscillator frequency, eq. 2: 2 pi (1 - beta) / T_sw (rad/s)."""
    return phi_aep(beta) / swing_duration


def nominal_speed(beta: float, stroke: float, swing_duration: float) -> float:
    """Walking speed of eq. 2, v = (1 - beta) D / (beta T_sw) (m/s)."""
    return (1.0 - beta) * stroke / (beta * swing_duration)


class ParameterRow(NamedTuple):
    """One parameter as the docs, `insect-gait params` and `GET /v1/model` show it."""

    name: str
    group: str
    value: object
    origin: str
    reason: str


def parameter_table(params: ModelParams | None = None) -> list[ParameterRow]:
    """Every parameter by group, with its value, origin (paper or invented) and reason. A
    ground's own constant is listed in group "contact (<ground> ground)", with its default
    where `params` stand on the other ground."""
    p = params or ModelParams()
    own_ground = {name: g for g, names in GROUND_ONLY.items() for name in names}
    rows: list[ParameterRow] = []
    for group, models in GROUPS.items():
        for model in models:
            for name, field in model.model_fields.items():
                if name in (row.name for row in rows):
                    continue  # shared by both grounds: listed once
                extra = field.json_schema_extra
                origin = extra.get("origin") if isinstance(extra, dict) else None
                if origin not in (PAPER, INVENTED):
                    raise TypeError(f"ModelParams.{group}.{name} says not whether it is ours")
                label = f"{group} ({own_ground[name]} ground)" if name in own_ground else group
                mine = name in type(getattr(p, group)).model_fields
                value = p.leaf(name) if mine else field.default  # the other ground's default
                reason = field.description or ""
                rows.append(ParameterRow(name, label, value, str(origin), reason))
    return rows

"""The foot-ground contact, declared: a `Ground` adds itself to the hexapod's MjSpec.

Two grounds, one chosen by `ModelParams.ground` through `ground_for`:

- `ConstraintGround` ("constraint", the default): MuJoCo's soft contact constraint between the
  foot spheres and the floor plane (solref/solimp, elliptic cone; the solver does the rest).
- `PenaltyGround` ("penalty"): the paper's viscoelastic elements. The feet collide with nothing
  (contact detection is switched off) and an engine plugin adds, at every physics evaluation,
  for each foot whose sphere dips below the floor (world z = 0; the core tilts gravity, not the
  floor):

      normal      F_n = max(0, k_n depth - c_n v_z)                  (never pulls)
      tangential  F_t = -k_t (p_xy - anchor_xy) - c_t v_xy            (anchored at touchdown)
                  |F_t| <= mu F_n: beyond it the anchor slides (Coulomb), so slip is measurable

  applied at the foot's centre through `mj_applyFT` into `qfrc_passive`. The anchor is set
  where the foot touched down and released when it lifts off.

How the penalty force is compiled and where its state lives: `penalty_ground.c` is a MuJoCo
engine plugin (`mjplugin.h`, capability mjPLUGIN_PASSIVE), compiled by `ground_build.py` (`make
plugin`, which `make run` and `make test` run; the Dockerfile's build stage runs the same) and
loaded into the process with `mj_loadPluginLibrary` the first time a penalty-ground spec is built.
MuJoCo calls it only for models that hold an instance of it, right after `mjcb_passive`, so no
other model sees it. Its parameters are the instance's config attributes (written with `repr`,
read with `strtod`: the same doubles), its foot sites are named in the config and resolved by
the plugin; the anchors and touch flags live in `plugin_state`, part of each simulation's
integration state (mjSTATE_PLUGIN), which `mujoco.batch` saves with each simulation's row.

Under RK4 the force runs at each of the four stages and may move the anchor mid-step; the anchor
is a slow variable (it moves only when the foot lands or slides), so this is an explicit update
of a quasi-static state.
"""

from __future__ import annotations

import functools
from abc import ABC, abstractmethod
from dataclasses import dataclass

import mujoco

from sim_core.model import ground_build
from sim_core.model.anatomy import LEG_NAMES
from sim_core.model.params import ModelParams

N_FEET = len(LEG_NAMES)
PLUGIN_INSTANCE = "penalty_ground"


def foot_geom(leg: str) -> str:
    """The name of a leg's foot sphere in the hexapod's spec (mjspec.py)."""
    return f"{leg}_foot"


def foot_site(leg: str) -> str:
    """The name of the site at a leg's foot centre (the touch sense and the penalty point)."""
    return f"{leg}_foot_site"


class Ground(ABC):
    """A foot-ground contact model: `add_to` makes a spec's feet stand on it.

    The spec must hold the six feet (`foot_geom`, `foot_site` names); everything the ground
    needs travels in the compiled model, so a model, its batch copies and every MjData made
    from them need no further set-up.
    """

    @abstractmethod
    def add_to(self, spec: mujoco.MjSpec) -> None:
        """Configure `spec`'s feet (and options) for this ground."""


@dataclass(frozen=True)
class ConstraintGround(Ground):
    """MuJoCo's contact constraint: the feet collide with the floor (the only geoms that do)."""

    friction: tuple[float, float, float]  # sliding, torsional, rolling
    solref: tuple[float, float]  # time constant s, damping ratio
    solimp: tuple[float, float, float, float, float]  # dmin, dmax, width m, midpoint, power

    def add_to(self, spec: mujoco.MjSpec) -> None:
        for leg in LEG_NAMES:
            foot = spec.geom(foot_geom(leg))
            foot.contype = 1
            foot.condim = 3
            foot.friction = list(self.friction)
            foot.solref = list(self.solref)
            foot.solimp = list(self.solimp)
            foot.priority = 1  # the foot's contact parameters win over the floor's defaults


@dataclass(frozen=True)
class PenaltyGround(Ground):
    """The paper's viscoelastic feet (SI units: N/m, N s/m, m), as a MuJoCo engine plugin."""

    stiffness: float
    damping: float
    tangential_stiffness: float
    tangential_damping: float
    friction: float
    foot_radius: float

    def add_to(self, spec: mujoco.MjSpec) -> None:
        # nothing collides: skip collision detection altogether
        spec.option.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
        for leg in LEG_NAMES:
            spec.geom(foot_geom(leg)).contype = 0
        name = load_plugin()
        spec.activate_plugin(name)
        plugin = spec.add_plugin(name=PLUGIN_INSTANCE, plugin_name=name, active=True)
        plugin.config = self.config()

    def config(self) -> dict[str, str]:
        """The plugin instance's attributes (penalty_ground.c reads them at mj_makeData)."""
        numbers = {
            "stiffness": self.stiffness,
            "damping": self.damping,
            "tangential_stiffness": self.tangential_stiffness,
            "tangential_damping": self.tangential_damping,
            "friction": self.friction,
            "radius": self.foot_radius,
        }
        # repr is the shortest string that reads back as the same double (strtod in C)
        return {k: repr(float(v)) for k, v in numbers.items()} | {
            "sites": " ".join(foot_site(leg) for leg in LEG_NAMES)
        }


def ground_for(p: ModelParams) -> Ground:
    """The ground `p.contact.ground` names, with its parameters from `p`."""
    c = p.contact
    if c.ground == "penalty":
        return PenaltyGround(
            stiffness=c.ground_stiffness,
            damping=c.ground_damping,
            tangential_stiffness=c.ground_tangential_stiffness,
            tangential_damping=c.ground_tangential_damping,
            friction=c.friction,
            foot_radius=p.legs.foot_radius,
        )
    return ConstraintGround(
        friction=(c.friction, c.torsional_friction, c.rolling_friction),
        solref=(c.contact_timeconst, c.contact_dampratio),
        solimp=(c.contact_dmin, c.contact_dmax, p.legs.foot_radius * c.contact_width_share,
                c.contact_midpoint, c.contact_power),
    )  # fmt: skip


@functools.cache
def load_plugin() -> str:
    """Load the penalty ground's compiled plugin into this process (once); its plugin name.

    Raises:
        RuntimeError: the library is missing, was built for another MuJoCo, or from another
            version of penalty_ground.c.
    """
    rebuild = "build it with `make plugin` (python -m sim_core.model.ground_build)"
    library = ground_build.LIBRARY
    if not library.exists():
        raise RuntimeError(f"the penalty ground's plugin {library} is not built: {rebuild}")
    try:
        mujoco.mj_loadPluginLibrary(str(library))
    except mujoco.FatalError as exc:  # e.g. linked to another MuJoCo version's libmujoco
        raise RuntimeError(f"cannot load {library} ({exc}): {rebuild}") from exc
    name = ground_build.plugin_name()
    check = mujoco.MjSpec()  # the smallest model that holds an instance: six sites
    body = check.worldbody.add_body()
    for leg in LEG_NAMES:
        body.add_site(name=foot_site(leg))
    check.activate_plugin(name)
    plugin = check.add_plugin(name=PLUGIN_INSTANCE, plugin_name=name, active=True)
    plugin.config = PenaltyGround(1.0, 0.0, 1.0, 0.0, 1.0, 1e-3).config()
    try:
        check.compile()
    except ValueError as exc:
        raise RuntimeError(
            f"{library} does not register {name}: it was built from another version of "
            f"penalty_ground.c; {rebuild}"
        ) from exc
    return name

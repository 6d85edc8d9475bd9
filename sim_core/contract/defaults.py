"""The model's default numerics and the grounds' words, as the edges show them: the API's
defaults and meta route, the CLI's help and the viewer's buttons read them here, so none of
them builds a `ModelParams` or retypes a sentence."""

from __future__ import annotations

from sim_core.model.params import Integrator, ModelParams

_DEFAULTS = ModelParams()
DEFAULT_INTEGRATOR: Integrator = _DEFAULTS.numerics.integrator
DEFAULT_DT_S: float = _DEFAULTS.numerics.dt
DEFAULT_CONTROL_DT_S: float = _DEFAULTS.numerics.control_dt
# The grounds go by one name everywhere: `ModelParams.ground`'s, which the API's `ground`
# field, the CLI's `--ground`, the result files' names and the viewer's buttons all say; what
# each is, in words, follows the name where a person chooses one (help texts, the viewer).
GROUND_WORDS: dict[str, str] = {
    "constraint": "MuJoCo's soft contact, the default",
    "penalty": "the paper's viscoelastic feet, which keep the heading on slopes",
}
GROUND_HELP = "; ".join(f"{g}: {w}" for g, w in GROUND_WORDS.items())

"""What the edges validate against and analyse with, importable without MuJoCo or numba.

The REST API refuses a request at the door and the CLI refuses a command line with these rules
and words; the API's job kinds and `reproduce` read runs with these analyses. They live in the
core (one home, nothing mirrored) and load in a few hundred milliseconds: pydantic and numpy,
no physics engine, no compiler. `tests/core/test_architecture.py` keeps it so.

Why a module and a lazy `sim_core/__init__` both: the lazy package (PEP 562) makes
`import sim_core` cheap for everybody, including a worker process that re-imports the
`insect-gait` script; this module says which names are the contract, so that the API imports
exactly those and a test can hold them to "no MuJoCo".
"""

from __future__ import annotations

from sim_core.model.anatomy import LEG_NAMES
from sim_core.model.gait import (
    TAIL_DRIFT_SETTLED,
    circular_mean,
    classify_gait,
    final_d31,
    mean_after,
    settled_gait,
    tail_drift,
)
from sim_core.model.params import (
    INTEGRATORS,
    MAX_STABLE_DT_S,
    Integrator,
    ModelParams,
    parameter_table,
    step_problem,
)
from sim_core.model.ramp import RAMP_PARAMS, Ramp, RampParam
from sim_core.model.spec import (
    FAILURE_KINDS,
    FailureKind,
    RunFailure,
    RunSpec,
    numerics_problem,
    resolve_numerics,
)
from sim_core.paper.fixedpoints import (
    AXIS_LABEL,
    REGIONS,
    AtlasOutput,
    CellResult,
    FinderOutput,
    region_of,
)
from sim_core.paper.returnmap import RETURN_MAP_SKIP, ReturnMap, return_map_from_series

_DEFAULTS = ModelParams()
DEFAULT_INTEGRATOR: Integrator = _DEFAULTS.integrator
DEFAULT_DT_S: float = _DEFAULTS.dt
DEFAULT_CONTROL_DT_S: float = _DEFAULTS.control_dt

__all__ = [
    "AXIS_LABEL",
    "DEFAULT_CONTROL_DT_S",
    "DEFAULT_DT_S",
    "DEFAULT_INTEGRATOR",
    "FAILURE_KINDS",
    "INTEGRATORS",
    "LEG_NAMES",
    "MAX_STABLE_DT_S",
    "RAMP_PARAMS",
    "REGIONS",
    "RETURN_MAP_SKIP",
    "TAIL_DRIFT_SETTLED",
    "AtlasOutput",
    "CellResult",
    "FailureKind",
    "FinderOutput",
    "Integrator",
    "ModelParams",
    "Ramp",
    "RampParam",
    "ReturnMap",
    "RunFailure",
    "RunSpec",
    "circular_mean",
    "classify_gait",
    "final_d31",
    "mean_after",
    "numerics_problem",
    "parameter_table",
    "region_of",
    "resolve_numerics",
    "return_map_from_series",
    "settled_gait",
    "step_problem",
    "tail_drift",
]

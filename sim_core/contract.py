"""What the edges validate against and analyse with, importable without MuJoCo or numba.

The REST API refuses a request at the door and the CLI refuses a command line with these rules
and words; the API's job kinds and `reproduce` read runs with these analyses. They live in the
core (one home, nothing mirrored) and load in a few hundred milliseconds: pydantic and numpy,
no physics engine, no compiler. `tests/core/test_architecture.py` keeps it so.

Why a module and a lazy `sim_core/__init__` both: the lazy package (PEP 562) makes
`import sim_core` cheap for everybody, including a worker process that re-imports the
`insect-gait` script; this module says which names are the contract, so that the API imports
exactly those and a test can hold them to "no MuJoCo".

The lab (lab/, `python -m lab`) reads its runs with the same analyses; a name commented
`# research:` is here for it (and anyone studying the model from outside the package), not for
the edges.
"""

from __future__ import annotations

from sim_core.model.anatomy import LEG_NAMES
from sim_core.model.cost import (
    MAX_JOB_BYTES,
    MAX_STEPS_PER_RUN,
    MIN_DT_S,
    RECORD_DT_S,
    RunCost,
    run_cost,
)
from sim_core.model.gait import (
    HEADING_KEPT_DEG,  # research: a heading kept within this, deg (slope studies)
    METACHRONAL,
    NOT_SETTLED,
    TAIL_DRIFT_SETTLED,
    TRIPOD,
    TWO_PI,
    Settling,
    angle_diff,  # research: the signed difference of angles, wrapped (every comparison)
    circular_mean,
    classify_gait,
    drift_per_cycle,  # research: Delta31's drift per cycle from the legs' phase jumps
    final_d31,
    mean_after,
    phase_jumps,  # research: eq. 4's jumps at touchdown, per leg
    settling,
    window_d31,  # research: where Delta31 sits now (`window_gait`'s reading; short screens)
    window_gait,
    yaw_of,  # research: the body's heading from its quaternions
)
from sim_core.model.params import (
    GROUND_DEFAULT,
    GROUND_ONLY,
    GROUNDS,
    INTEGRATORS,
    MAX_STABLE_DT_S,
    PARAMETER_NAMES,
    Integrator,
    ModelParams,
    parameter_table,
    step_problem,
)
from sim_core.model.ramp import RAMP_PARAMS, EventConditions, Ramp, RampParam
from sim_core.model.spec import (
    FAILURE_KINDS,
    INSECT_WORDS,
    MASS_MAX_G,
    MASS_MIN_G,
    MASS_REASON,
    NO_FOOTHOLD_S,
    SLIDE_BACK_SPEED_M_S,
    SLIDE_WINDOW_S,
    FailureKind,
    RunFailure,
    RunMeasures,
    RunSpec,
    control_problem,
    cost_problem,
    numerics_problem,
    pin_problem,
    resolve_numerics,
)
from sim_core.model.version import PHYSICS_VERSION
from sim_core.paper.fixedpoints import (
    AXIS_LABEL,
    AXIS_PARAM,
    REGIONS,
    AtlasAxis,
    AtlasOutput,
    Cell,
    CellResult,
    FinderConfig,
    FinderOutput,
    Probe,
    branch_ranges,  # research: each gait's stable range and folds in the finder's cells
    cluster_finals,  # research: settled ends clustered as the finder clusters them
    find,
    region_of,
)
from sim_core.paper.results import (
    ATLAS_AXES,
    BIFURCATION_FILE,
    RESULTS_DIR,
    RESULTS_ENV,
    SURFACE_FILE,
    atlas_file,
    surface_atlas_file,
)
from sim_core.paper.returnmap import (
    RETURN_MAP_SKIP,
    ReturnMap,
    initial_values,  # research: the protocols' starts, spread over the circle
    return_map_from_series,
)
from sim_core.paper.surface_types import REGION_COLOURS, DriftSurface, SurfaceAtlas, SurfaceConfig
from sim_core.paper.surface_types import grid as surface_grid
from sim_core.paper.values import PAPER, PaperValues  # what the paper states: panels beside ours
from sim_core.runs.keys import params_hash, provenance  # a file's physics, as the cache names it

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

__all__ = [
    "ATLAS_AXES",
    "AXIS_LABEL",
    "AXIS_PARAM",
    "BIFURCATION_FILE",
    "DEFAULT_CONTROL_DT_S",
    "DEFAULT_DT_S",
    "DEFAULT_INTEGRATOR",
    "FAILURE_KINDS",
    "GROUNDS",
    "GROUND_DEFAULT",
    "GROUND_HELP",
    "GROUND_ONLY",
    "GROUND_WORDS",
    "HEADING_KEPT_DEG",
    "INSECT_WORDS",
    "INTEGRATORS",
    "LEG_NAMES",
    "MASS_MAX_G",
    "MASS_MIN_G",
    "MASS_REASON",
    "MAX_JOB_BYTES",
    "MAX_STABLE_DT_S",
    "MAX_STEPS_PER_RUN",
    "METACHRONAL",
    "MIN_DT_S",
    "NOT_SETTLED",
    "NO_FOOTHOLD_S",
    "PAPER",
    "PARAMETER_NAMES",
    "PHYSICS_VERSION",
    "RAMP_PARAMS",
    "RECORD_DT_S",
    "REGIONS",
    "REGION_COLOURS",
    "RESULTS_DIR",
    "RESULTS_ENV",
    "RETURN_MAP_SKIP",
    "SLIDE_BACK_SPEED_M_S",
    "SLIDE_WINDOW_S",
    "SURFACE_FILE",
    "TAIL_DRIFT_SETTLED",
    "TRIPOD",
    "TWO_PI",
    "AtlasAxis",
    "AtlasOutput",
    "Cell",
    "CellResult",
    "DriftSurface",
    "EventConditions",
    "FailureKind",
    "FinderConfig",
    "FinderOutput",
    "Integrator",
    "ModelParams",
    "PaperValues",
    "Probe",
    "Ramp",
    "RampParam",
    "ReturnMap",
    "RunCost",
    "RunFailure",
    "RunMeasures",
    "RunSpec",
    "Settling",
    "SurfaceAtlas",
    "SurfaceConfig",
    "angle_diff",
    "atlas_file",
    "branch_ranges",
    "circular_mean",
    "classify_gait",
    "cluster_finals",
    "control_problem",
    "cost_problem",
    "drift_per_cycle",
    "final_d31",
    "find",
    "initial_values",
    "mean_after",
    "numerics_problem",
    "parameter_table",
    "params_hash",
    "phase_jumps",
    "pin_problem",
    "provenance",
    "region_of",
    "resolve_numerics",
    "return_map_from_series",
    "run_cost",
    "settling",
    "step_problem",
    "surface_atlas_file",
    "surface_grid",
    "window_d31",
    "window_gait",
    "yaw_of",
]

"""What the edges validate against and analyse with, importable without MuJoCo or numba.

The REST API refuses a request at the door and the CLI refuses a command line with these rules
and words; the API's job kinds, `reproduce` and the viewer read runs and result files with
these analyses and schemas. They live in the core (one home, nothing mirrored) and load in a
few hundred milliseconds: pydantic and numpy, no physics engine, no compiler.
`tests/core/test_architecture.py` keeps it so.

A package of its own, below the reproduction (`sim_core.paper`, which imports it and never
the other way; pyproject's import-linter layers): the run's rules come from the model and are
named here; what the instruments produce is defined here, each in a small module by concern:

- `finder`: the fixed-point finder's protocol (`FinderConfig`, `Cell`, `Probe`, and `RunFn`,
  what the search asks of its caller) and typed output (bifurcation.json), and its gait
  atlas's (atlas_<axis>.json);
- `surface`: the drift surface's protocol and result (`DriftSurface`) and the surface atlas
  (`SurfaceAtlas`, the viewer's atlas panel);
- `summaries`: a run's summary and record (`RunSummary`, `RunRecord`, generated from the run's
  records' fields) and a triangle sweep's (`SweepSummary`), the REST results' leaves;
- `template`: the run template (`RunTemplate`: RunSpec bar what an instrument sets run by run),
  from which every REST job and the instruments compose their runs' specs;
- `returnmap`: the paper's Fig. 7 pairs (`ReturnMap`); `results`: where result files live;
  `values`: what the paper states; `defaults`: the model's default numerics and the grounds'
  words.

A schema package: types, their validators and readings (methods, properties), the constants
they name and a few pure helpers on them (`region_of`, `surface_grid`, the result files'
names). What computes results lives above it in `sim_core.paper`: the finder's search
(`paper.finder`, `find`: the package root's, for the REST `bifurcation` kind) and what it reads
off runs (`paper.finder_runs`), the return map's pairs (`paper.returnmap`,
`return_map_from_series`: the root's, for the REST kind and the viewer).

The face is the imports below, listed once: every public name they bind is in `__all__`.
The lab's further names (readings of a run, the finder's clustering and branch ranges) are
`sim_core.research`'s.
"""

from types import ModuleType as _ModuleType

from sim_core.contract.choice import ModelChoice  # a run's model parameters, as edges take them
from sim_core.contract.defaults import (
    DEFAULT_CONTROL_DT_S,
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    GROUND_HELP,
    GROUND_WORDS,
)
from sim_core.contract.finder import (
    AXIS_LABEL,
    AXIS_PARAM,
    REGIONS,
    AtlasOutput,
    Cell,
    CellResult,
    FinderConfig,
    FinderOutput,
    Probe,
    RunFn,
    region_of,
)
from sim_core.contract.results import (
    ATLAS_AXES,
    BIFURCATION_FILE,
    RESULTS_DIR,
    RESULTS_ENV,
    SURFACE_FILE,
    AtlasAxis,
    atlas_file,
    surface_atlas_file,
)
from sim_core.contract.returnmap import RETURN_MAP_SKIP, ReturnMap
from sim_core.contract.summaries import (
    SUMMARY_MEASURES,
    RunRecord,
    RunSummary,
    SweepSummary,
    SweepTransition,
)
from sim_core.contract.surface import (
    REGION_COLOURS,
    SHORT_PROBES,
    DriftSurface,
    SurfaceAtlas,
    SurfaceConfig,
)
from sim_core.contract.surface import grid as surface_grid
from sim_core.contract.template import RunTemplate  # RunSpec bar the per-run fields
from sim_core.contract.values import PAPER, PaperValues  # what the paper states: beside ours
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
    METACHRONAL,
    NOT_SETTLED,
    TAIL_DRIFT_SETTLED,
    TRIPOD,
    TWO_PI,
    Settling,
    circular_mean,
    classify_gait,
    final_d31,
    mean_after,
    settling,
    window_gait,
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
from sim_core.runs.keys import params_hash, provenance  # a file's physics, as the cache names it

# the names bound above; not the submodules, which importing them binds here too
__all__ = sorted(
    name
    for name, value in globals().items()
    if not name.startswith("_") and not isinstance(value, _ModuleType)
)

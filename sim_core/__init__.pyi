"""The public API, listed once: type checkers read these imports, and `lazy_loader` turns
them into names that load on first use (sim_core/__init__.py).

Two audiences, one list. The product's names (no comment) are what server/ and web/ build on.
A name with a `# research:` comment is there for the lab (lab/, `python -m lab`) and anyone
studying the model from outside the package; the comment says why it is public. The lab, like
the edges, imports only `sim_core`, `sim_core.contract` and `sim_core.cli` (pyproject's
import-linter contracts, tests/core/test_architecture.py)."""

# `name as name`: an explicit re-export, for type checkers and linters
from .model.anatomy import (
    attachment_points as attachment_points,  # research: the hips, in the body frame
)
from .model.anatomy import leg_names as leg_names
from .model.cpg import (
    advance_phases as advance_phases,  # research: eq. 1's step (numba), for reduced models
)
from .model.gait import circular_mean as circular_mean
from .model.gait import classify_gait as classify_gait
from .model.legs import (
    inverse_kinematics as inverse_kinematics,  # research: leg kinematics (reach checks)
)
from .model.legs import (
    leg_geometry as leg_geometry,  # research: leg kinematics (reach checks)
)
from .model.legs import (
    swing_point as swing_point,  # research: leg kinematics (reach checks)
)
from .model.live import Simulation as Simulation
from .model.mjspec import build_model as build_model
from .model.mjspec import (
    leg_qpos_addresses as leg_qpos_addresses,  # research: pose a `build_model` model
)
from .model.mjspec import (
    mid_stance_angles as mid_stance_angles,  # research: pose a `build_model` model
)
from .model.params import (
    INTEGRATORS as INTEGRATORS,
)
from .model.params import (
    MAX_STABLE_DT_S as MAX_STABLE_DT_S,
)
from .model.params import (
    ModelParams as ModelParams,
)
from .model.params import (
    nominal_speed as nominal_speed,
)
from .model.params import (
    parameter_table as parameter_table,
)
from .model.params import (
    phi_aep as phi_aep,  # research: the AEP's phase, 2 pi (1 - beta) (Sec. II B 2)
)
from .model.params import (
    step_problem as step_problem,
)
from .model.probes import (
    open_loop_drift as open_loop_drift,  # research: the drift probe (resets off, D31 held)
)
from .model.runner import (
    BatchRunner as BatchRunner,  # research: the one run loop, with a per-period hook
)
from .model.runner import simulate as simulate
from .model.runner import simulate_batch as simulate_batch
from .model.settings import (
    NAMED_SETTINGS as NAMED_SETTINGS,  # research: named regimes of invented parameters
)
from .model.settings import (
    named_params as named_params,  # research: a named regime as ModelParams
)
from .model.spec import (
    RunFailure as RunFailure,
)
from .model.spec import (
    RunResult as RunResult,
)
from .model.spec import (
    RunSpec as RunSpec,
)
from .model.spec import (
    SimulationDiverged as SimulationDiverged,
)
from .model.spec import (
    spec_grid as spec_grid,
)
from .paper.atlas import AtlasConfig as AtlasConfig
from .paper.atlas import atlas_search as atlas_search
from .paper.atlas import (
    run_atlas as run_atlas,  # research: `atlas_search` through the cache, on a backend
)
from .paper.atlas import (
    write_atlas as write_atlas,  # research: atlas_<axis>.json (the viewer reads it) and .png
)
from .paper.claims import (
    CALIBRATED as CALIBRATED,  # research: the calibrated parameters (the +-10% checks)
)
from .paper.claims import (
    SCALES as SCALES,  # research: the +-10% checks' scales
)
from .paper.claims import (
    scaled_values as scaled_values,  # research: the +-10% checks' variants
)
from .paper.figures import (
    ReproduceConfig as ReproduceConfig,  # research: `reproduce`'s protocol, to repeat it
)
from .paper.plots import (
    fig5 as fig5,  # research: the reproduction's Fig. 5 drawing of free runs
)
from .paper.search import (
    probe_task as probe_task,  # research: a finder run as its cached task (same key)
)
from .paper.search import (
    task_runner as task_runner,  # research: `find`'s runs as cached tasks on a backend
)
from .paper.surface import Condition as Condition
from .paper.surface import drift_surface as drift_surface
from .paper.surface import (
    grid_probes as grid_probes,  # research: a drift surface's first-pass probes
)
from .paper.surface import (
    probe_spec as probe_spec,  # research: a surface probe's pinned run (read back cached)
)
from .paper.surface_atlas import surface_atlas as surface_atlas
from .paper.surface_types import (
    DriftSurface as DriftSurface,
)
from .paper.surface_types import (
    SurfaceAtlas as SurfaceAtlas,
)
from .paper.surface_types import (
    SurfaceConfig as SurfaceConfig,
)
from .paper.surface_walks import WalkConfig as WalkConfig
from .paper.sweep import SweepResult as SweepResult
from .paper.sweep import sweep as sweep
from .paper.values import (
    BETA_BISTABLE as BETA_BISTABLE,  # research: what the paper states (scored against)
)
from .paper.values import (
    BETA_FAST as BETA_FAST,  # research: what the paper states (scored against)
)
from .paper.values import (
    BETA_SLOW as BETA_SLOW,  # research: what the paper states (scored against)
)
from .paper.values import (
    METACHRONAL_BRANCH as METACHRONAL_BRANCH,  # research: what the paper states
)
from .paper.values import (
    TRIPOD_BRANCH as TRIPOD_BRANCH,  # research: what the paper states (scored against)
)

# the runs' machinery: the REST service's jobs run their simulations through it (one result
# cache for every door), the lab's studies too
from .runs import (
    BACKENDS as BACKENDS,  # research: the backends' names (cached, resumable runs)
)
from .runs import cache_max_bytes_of as cache_max_bytes_of
from .runs import default_cache_dir as default_cache_dir
from .runs import default_cache_max_bytes as default_cache_max_bytes
from .runs.backends import Backend as Backend
from .runs.backends import BackendUnavailable as BackendUnavailable
from .runs.backends import RunStats as RunStats
from .runs.backends import get_backend as get_backend
from .runs.backends import run_tasks as run_tasks
from .runs.cache import ResultCache as ResultCache
from .runs.tasks import Task as Task
from .runs.tasks import execute_chunk as execute_chunk
from .runs.tasks import (
    ramp_task as ramp_task,  # research: a ramped run (a sweep) as a cached task
)
from .runs.tasks import run_task as run_task
from .runs.tasks import summary_of as summary_of

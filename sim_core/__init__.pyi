"""The public API, listed once: type checkers read these imports, and `lazy_loader` turns
them into names that load on first use (sim_core/__init__.py)."""

# `name as name`: an explicit re-export, for type checkers and linters
from .model.anatomy import leg_names as leg_names
from .model.gait import circular_mean as circular_mean
from .model.gait import classify_gait as classify_gait
from .model.live import Simulation as Simulation
from .model.mjspec import build_model as build_model
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
    step_problem as step_problem,
)
from .model.runner import simulate as simulate
from .model.runner import simulate_batch as simulate_batch
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
from .paper.surface import Condition as Condition
from .paper.surface import drift_surface as drift_surface
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
from .paper.sweep import SweepResult as SweepResult
from .paper.sweep import sweep as sweep

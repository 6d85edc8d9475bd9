"""The product's API, listed once: type checkers read these imports, and `lazy_loader` turns
them into names that load on first use (sim_core/__init__.py).

These are the names server/ and web/ build on (and the examples show): a run's spec and
result, the engine's entry points, the cached tasks a job's worker executes, and the
instruments the REST kinds call. The MuJoCo-free rules, words and schemas are
`sim_core.contract`'s; the names only the lab needs are `sim_core.research`'s (one face per
name: tests/core/test_architecture.py)."""

# `name as name`: an explicit re-export, for type checkers and linters
from .contract.surface import WalkConfig as WalkConfig
from .model.live import Simulation as Simulation
from .model.params import ModelParams as ModelParams
from .model.params import nominal_speed as nominal_speed
from .model.runner import simulate as simulate
from .model.runner import simulate_batch as simulate_batch
from .model.spec import RunResult as RunResult
from .model.spec import RunSpec as RunSpec
from .model.spec import spec_grid as spec_grid
from .paper.finder import find as find  # the REST `bifurcation` kind's search (engine-free)
from .paper.returnmap import (
    return_map_from_series as return_map_from_series,  # Fig. 7's pairs: REST kind, viewer
)
from .paper.surface import drift_surface as drift_surface
from .paper.surface_atlas import surface_atlas as surface_atlas
from .paper.sweep import sweep as sweep

# the runs' machinery: the REST service's jobs run their simulations through it (one result
# cache for every door: issue 54)
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
from .runs.tasks import run_task as run_task
from .runs.tasks import summary_of as summary_of

"""insect-gait core: the Fujiki et al. (2013) hexapod in MuJoCo, headless and batchable.

Public API (server/ and web/ use only these names, or `sim_core.contract`):

    from sim_core import RunSpec, simulate, simulate_batch, Simulation, ModelParams

    result = simulate(RunSpec(beta=0.62, d31_init=2.0, duration_s=5.0))
    result.summary()   # {'d31': [...], 'd31_final': ..., 'gait': 'tripod', ...}

    results = simulate_batch([RunSpec(beta=b) for b in (0.62, 0.70)])

    sim = Simulation(RunSpec(beta=0.66))   # live, steppable; the viewer's engine
    sim.advance(0.1); sim.set_beta(0.63)

Names load on first use (PEP 562): `import sim_core` and the MuJoCo-free contract
(`sim_core.contract`: RunSpec, integrators and their limits, leg names, failure kinds, the
analyses) cost no MuJoCo or numba import; the engine's names (`simulate`, `Simulation`, ...) load
it when first touched.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

# public name -> the module that defines it
_HOME: dict[str, str] = {
    "INTEGRATORS": "sim_core.model.params",
    "MAX_STABLE_DT_S": "sim_core.model.params",
    "ModelParams": "sim_core.model.params",
    "nominal_speed": "sim_core.model.params",
    "parameter_table": "sim_core.model.params",
    "step_problem": "sim_core.model.params",
    "RunFailure": "sim_core.model.spec",
    "RunResult": "sim_core.model.spec",
    "RunSpec": "sim_core.model.spec",
    "SimulationDiverged": "sim_core.model.spec",
    "spec_grid": "sim_core.model.spec",
    "circular_mean": "sim_core.model.gait",
    "classify_gait": "sim_core.model.gait",
    "leg_names": "sim_core.model.anatomy",
    "Simulation": "sim_core.model.live",
    "build_model": "sim_core.model.mjspec",
    "simulate": "sim_core.model.runner",
    "simulate_batch": "sim_core.model.runner",
    "SweepResult": "sim_core.paper.sweep",
    "AtlasConfig": "sim_core.paper.atlas",
    "atlas_search": "sim_core.paper.atlas",
    "sweep": "sim_core.paper.sweep",
    "DriftSurface": "sim_core.paper.surface_types",
    "SurfaceConfig": "sim_core.paper.surface_types",
    "drift_surface": "sim_core.paper.surface",
    "Condition": "sim_core.paper.surface",
    "SurfaceAtlas": "sim_core.paper.surface_types",
    "surface_atlas": "sim_core.paper.surface_atlas",
}

__all__ = [
    "INTEGRATORS",
    "MAX_STABLE_DT_S",
    "AtlasConfig",
    "Condition",
    "DriftSurface",
    "ModelParams",
    "RunFailure",
    "RunResult",
    "RunSpec",
    "Simulation",
    "SimulationDiverged",
    "SurfaceAtlas",
    "SurfaceConfig",
    "SweepResult",
    "atlas_search",
    "build_model",
    "circular_mean",
    "classify_gait",
    "drift_surface",
    "leg_names",
    "nominal_speed",
    "parameter_table",
    "simulate",
    "simulate_batch",
    "spec_grid",
    "step_problem",
    "surface_atlas",
    "sweep",
]


def __getattr__(name: str) -> Any:
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module 'sim_core' has no attribute {name!r}")
    value = getattr(import_module(home), name)
    globals()[name] = value  # later lookups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_HOME))


if TYPE_CHECKING:  # what type checkers and IDEs see: the same names, eagerly
    from sim_core.model.anatomy import leg_names
    from sim_core.model.gait import circular_mean, classify_gait
    from sim_core.model.live import Simulation
    from sim_core.model.mjspec import build_model
    from sim_core.model.params import (
        INTEGRATORS,
        MAX_STABLE_DT_S,
        ModelParams,
        nominal_speed,
        parameter_table,
        step_problem,
    )
    from sim_core.model.runner import simulate, simulate_batch
    from sim_core.model.spec import (
        RunFailure,
        RunResult,
        RunSpec,
        SimulationDiverged,
        spec_grid,
    )
    from sim_core.paper.atlas import AtlasConfig, atlas_search
    from sim_core.paper.surface import Condition, drift_surface
    from sim_core.paper.surface_atlas import surface_atlas
    from sim_core.paper.surface_types import DriftSurface, SurfaceAtlas, SurfaceConfig
    from sim_core.paper.sweep import SweepResult, sweep

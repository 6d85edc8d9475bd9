"""insect-gait core: the Fujiki et al. (2013) hexapod in MuJoCo, headless and batchable.

Public API (server/ and web/ use only these names):

    from sim_core import RunSpec, simulate, simulate_batch, Simulation, ModelParams

    result = simulate(RunSpec(beta=0.62, d31_init=2.0, duration_s=5.0))
    result.summary()   # {'d31': [...], 'd31_final': ..., 'gait': 'tripod', ...}

    results = simulate_batch([RunSpec(beta=b) for b in (0.62, 0.70)])

    sim = Simulation(RunSpec(beta=0.66))   # live, steppable; the viewer's engine
    sim.advance(0.1); sim.set_beta(0.63)
"""

from sim_core.model.anatomy import leg_names
from sim_core.model.gait import circular_mean, classify_gait
from sim_core.model.live import Simulation
from sim_core.model.mjspec import build_model
from sim_core.model.params import INTEGRATORS, ModelParams, nominal_speed, parameter_table
from sim_core.model.runner import simulate, simulate_batch
from sim_core.model.spec import RunResult, RunSpec, SimulationDiverged, spec_grid
from sim_core.paper.sweep import SweepResult, sweep

__all__ = [
    "INTEGRATORS",
    "ModelParams",
    "RunResult",
    "RunSpec",
    "Simulation",
    "SimulationDiverged",
    "SweepResult",
    "build_model",
    "circular_mean",
    "classify_gait",
    "leg_names",
    "nominal_speed",
    "parameter_table",
    "simulate",
    "simulate_batch",
    "spec_grid",
    "sweep",
]

"""insect-gait core: the Fujiki et al. (2013) hexapod in MuJoCo, headless and batchable.

Public API (server/ and web/ use only these names, `sim_core.contract` and `sim_core.cli`;
the lab those and its own face, `sim_core.research`; docs/CORE_API.md):

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

import lazy_loader

# The public names are the imports of __init__.pyi (one list, read by type checkers too);
# each loads on first use (PEP 562), so `import sim_core` costs no MuJoCo or numba import.
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)

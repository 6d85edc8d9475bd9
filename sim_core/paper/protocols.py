"""The paper's return maps, run: simulations from initial values spread over the circle, read
as Fig. 7 pairs (the starts and the pairs' construction are `returnmap`'s, MuJoCo-free; the
typed output is the contract's)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from sim_core.contract.returnmap import RETURN_MAP_SKIP, ReturnMap
from sim_core.model.params import ModelParams
from sim_core.model.runner import simulate_batch
from sim_core.model.spec import spec_grid
from sim_core.paper.returnmap import return_map_from_series


def return_map(
    params: ModelParams | None,
    *,
    beta: float,
    inits: Sequence[float],
    duration_s: float = 2.0,
    lag: int = 4,
    skip: int = RETURN_MAP_SKIP,
    dt_s: float | None = None,
    nthread: int = 0,
    **fields: Any,
) -> ReturnMap:
    """Delta31(n) -> Delta31(n + lag) from many initial values (first `skip` cycles dropped);
    `fields`: the other RunSpec fields every run shares (body mass, slope, numerics, ...)."""
    specs = spec_grid([beta], inits, duration_s=duration_s, dt_s=dt_s, **fields)
    runs = simulate_batch(specs, params, nthread=nthread)
    return return_map_from_series(beta, [r.events.d31 for r in runs if not r.diverged], lag, skip)

"""The paper's return map (Fig. 7) built from series: the starts spread over the circle that
its protocols (and the finder's) run from, and the pairs (Delta31_n, Delta31_n+lag) read off
stored Delta31 series (the typed output, `ReturnMap`, is the contract's).

Pure numpy, no engine: the REST API's return-map jobs and the viewer call
`return_map_from_series` through the package root (`sim_core`), `reproduce` and
`protocols.return_map` here, so that every Fig. 7 is built by one function.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from sim_core.contract.returnmap import RETURN_MAP_SKIP, ReturnMap
from sim_core.model.gait import TWO_PI


def initial_values(n: int) -> np.ndarray:
    """n initial Delta31 spread evenly over the circle (offset off the symmetric points)."""
    return np.linspace(0.0, TWO_PI, n, endpoint=False) + math.pi / n


def return_map_from_series(
    beta: float,
    series: Sequence[Sequence[float] | np.ndarray],
    lag: int = 4,
    skip: int = RETURN_MAP_SKIP,
) -> ReturnMap:
    """Pairs (Delta31_n, Delta31_n+lag) from stored Delta31 series, first `skip` dropped.

    The one construction of the paper's Fig. 7 pairs; `return_map` runs the simulations first.
    """
    xs: list[float] = []
    ys: list[float] = []
    for s in series:
        d = np.asarray(s, dtype=float)[skip:]
        if d.size <= lag:
            continue
        xs.extend(d[:-lag].tolist())
        ys.extend(d[lag:].tolist())
    return ReturnMap(beta=beta, lag=lag, x=np.array(xs), y=np.array(ys))

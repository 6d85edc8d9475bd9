"""The paper's return map (Fig. 7): pairs (Delta31_n, Delta31_n+lag) at leg-1 touchdowns.

MuJoCo-free, so that the REST API's return-map jobs and `reproduce` build their pairs with the
same function (`sim_core.contract`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sim_core.model.gait import TWO_PI, angle_diff

# touchdowns dropped at the start of every series: the start's own transient (the first
# stance after the initial condition is not a gait cycle yet)
RETURN_MAP_SKIP = 2


@dataclass
class ReturnMap:
    """Pairs (Delta31_n, Delta31_{n+lag}) at leg-1 touchdowns, the paper's Fig. 7 construction."""

    beta: float
    lag: int
    x: np.ndarray
    y: np.ndarray

    def drift_per_cycle(self, bins: int = 24) -> tuple[np.ndarray, np.ndarray]:
        """Mean (y - x) / lag in bins of x over the circle: > 0 pushes Delta31 up."""
        edges = np.linspace(0, TWO_PI, bins + 1)
        d = angle_diff(self.y, self.x) / self.lag
        idx = np.clip(np.digitize(self.x, edges) - 1, 0, bins - 1)
        centers = 0.5 * (edges[1:] + edges[:-1])
        means = np.array([d[idx == k].mean() if (idx == k).any() else np.nan for k in range(bins)])
        return centers, means


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

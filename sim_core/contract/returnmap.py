"""The paper's return map (Fig. 7): its typed output, pairs (Delta31_n, Delta31_n+lag) at leg-1
touchdowns, and how many touchdowns each series drops first.

The pairs are built by `sim_core.paper.returnmap` (from stored series; MuJoCo-free, so the REST
API's return-map jobs, the viewer and `reproduce` build them with one function) and
`sim_core.paper.protocols.return_map` (which runs the simulations first).
"""

from __future__ import annotations

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

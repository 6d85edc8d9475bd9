"""Where the insect faces, and how fast it walks that way, from the body's pose alone.

The core's `Simulation.speed_cm_s` is the rate along world x: right while the insect walks
straight, wrong once it has turned (after sliding on a +30 degree slope the body ended turned,
and the readout said -0.26 cm/s on flat ground for minutes while it walked forwards). The
viewer computes its own readout from public state (`Simulation.data.qpos`: the free joint's
position and quaternion): the displacement over the last second projected on the body's
heading, the horizontal direction of its x axis (the model's forward axis,
sim_core/model/mjspec.py). The floor is the world's z = 0 plane at every slope (the core tilts
gravity, not the floor), so "horizontal" is the xy plane.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np


def yaw_of(wxyz: np.ndarray | list[float] | tuple[float, ...]) -> float:
    """Heading (rad, from world +x towards +y) of the body's x axis for a unit quaternion wxyz."""
    w, x, y, z = (float(c) for c in wxyz)
    # first column of the rotation matrix: the body's x axis in world coordinates
    return math.atan2(2.0 * (x * y + w * z), 1.0 - 2.0 * (y * y + z * z))


class HeadingSpeed:
    """Speed along the heading and a smoothed heading, over the last `window_s` simulated s.

    Feed it the body's pose once per frame (`add`); time going backwards means a reset and the
    record starts over.
    """

    def __init__(self, window_s: float = 1.0, maxlen: int = 2_000) -> None:
        if window_s <= 0:
            raise ValueError(f"window must be positive, got {window_s}")
        self.window_s = window_s
        self._s: deque[tuple[float, float, float, float]] = deque(maxlen=maxlen)

    def clear(self) -> None:
        self._s.clear()

    def add(self, t: float, pos: np.ndarray, wxyz: np.ndarray) -> None:
        """Record the body at simulated time `t`: position (m, world) and orientation (wxyz)."""
        if self._s and t < self._s[-1][0]:
            self.clear()
        if self._s and t == self._s[-1][0]:
            self._s.pop()
        self._s.append((float(t), float(pos[0]), float(pos[1]), yaw_of(wxyz)))
        while len(self._s) > 2 and t - self._s[1][0] >= self.window_s:
            self._s.popleft()

    @property
    def heading_rad(self) -> float | None:
        """Mean heading over the window (a circular mean: -pi and pi are the same way)."""
        if not self._s:
            return None
        yaw = np.fromiter((s[3] for s in self._s), dtype=float, count=len(self._s))
        return float(math.atan2(np.sin(yaw).mean(), np.cos(yaw).mean()))

    @property
    def speed_cm_s(self) -> float | None:
        """Displacement over the window along the mean heading, in cm/s (negative: backwards)."""
        if len(self._s) < 2:
            return None
        t0, x0, y0, _ = self._s[0]
        t1, x1, y1, _ = self._s[-1]
        heading = self.heading_rad
        if t1 - t0 <= 0 or heading is None:
            return None
        along = (x1 - x0) * math.cos(heading) + (y1 - y0) * math.sin(heading)
        return 100.0 * along / (t1 - t0)

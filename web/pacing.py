"""Real-time bookkeeping for the loop: how much simulated time is due, and how fast we really go.

Pure (the caller passes the clock readings), so that "keeps real time, never spirals when the
machine is too slow, and says so" is tested without a browser or a physics engine.
"""

from __future__ import annotations

from collections import deque


class SimClock:
    """Simulated seconds owed to the wall clock at the chosen speed.

    If stepping cannot keep up, the debt would grow without bound and the viewer would lag
    further and further behind; instead it is capped at `max_lag_s` of wall time, so the viewer
    falls back to running as fast as it can, and the real-time factor readout shows the gap.
    """

    def __init__(self, max_lag_s: float = 0.2) -> None:
        self.max_lag_s = max_lag_s
        self.debt_s = 0.0
        self.lag_s = 0.0  # uncapped: how far behind the wall clock the walk is (the status)

    def reset(self) -> None:
        self.debt_s = 0.0
        self.lag_s = 0.0

    def tick(self, wall_dt_s: float, speed: float) -> float:
        """Add `wall_dt_s` of wall time at `speed`; returns the simulated seconds now due."""
        wall_dt_s = max(0.0, wall_dt_s)
        self.debt_s = min(self.debt_s + wall_dt_s * speed, self.max_lag_s * speed)
        self.lag_s += wall_dt_s * speed
        return self.debt_s

    def paid(self, sim_s: float) -> None:
        self.debt_s -= sim_s
        self.lag_s = max(0.0, self.lag_s - sim_s)


class RateMeter:
    """Rate of a counter over the last `window_s` of wall time (real-time factor, frame rate)."""

    def __init__(self, window_s: float = 1.0) -> None:
        self.window_s = window_s
        self._samples: deque[tuple[float, float]] = deque()

    def reset(self) -> None:
        self._samples.clear()

    def add(self, wall_s: float, total: float) -> None:
        """Record the counter's running `total` at wall time `wall_s`."""
        self._samples.append((wall_s, total))
        while len(self._samples) > 2 and wall_s - self._samples[1][0] >= self.window_s:
            self._samples.popleft()

    @property
    def rate(self) -> float | None:
        if len(self._samples) < 2:
            return None
        (w0, c0), (w1, c1) = self._samples[0], self._samples[-1]
        if w1 - w0 <= 0:
            return None
        return (c1 - c0) / (w1 - w0)

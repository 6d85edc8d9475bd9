"""Rolling records the panels draw from: stance samples (footfall diagram) and Delta31 events.

The loop samples stance far more often than it redraws (a swing lasts 34 ms, a frame 33 ms), so
the buffers keep raw samples and turn them into bars only when a panel is redrawn. Time going
backwards means the simulation was reset: the record starts over rather than drawing nonsense.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

N_LEGS = 6


class FootfallBuffer:
    """Stance samples over the last `window_s` simulated seconds."""

    def __init__(self, window_s: float = 3.0, max_samples: int = 20_000) -> None:
        if window_s <= 0:
            raise ValueError(f"window must be positive, got {window_s}")
        self.window_s = window_s
        self._t: deque[float] = deque(maxlen=max_samples)
        self._s: deque[np.ndarray] = deque(maxlen=max_samples)
        self.version = 0  # bumps on every change; lets the loop skip redrawing an idle plot

    def __len__(self) -> int:
        return len(self._t)

    def clear(self) -> None:
        self._t.clear()
        self._s.clear()
        self.version += 1

    @property
    def t_now(self) -> float | None:
        return self._t[-1] if self._t else None

    def append(self, t: float, stance: np.ndarray | list[bool]) -> None:
        s = np.asarray(stance, dtype=bool).reshape(-1)
        if s.shape != (N_LEGS,):
            raise ValueError(f"stance must have {N_LEGS} entries, got shape {s.shape}")
        if not math.isfinite(t):
            raise ValueError(f"time must be finite, got {t}")
        if self._t and t < self._t[-1]:
            self.clear()  # reset
        elif self._t and t == self._t[-1]:
            self._s[-1] = s.copy()  # same instant sampled twice: keep the latest
            self.version += 1
            return
        self._t.append(float(t))
        self._s.append(s.copy())
        # keep one sample before the window so the first bar starts at the window's edge
        horizon = t - self.window_s
        while len(self._t) > 1 and self._t[1] <= horizon:
            self._t.popleft()
            self._s.popleft()
        self.version += 1

    def bars(self) -> list[list[tuple[float, float]]]:
        """Per leg (paper order), (start, end) of stance bars clipped to the window.

        Sample i stands for [t_i, t_{i+1}); a bar still open at the last sample ends there.
        """
        out: list[list[tuple[float, float]]] = [[] for _ in range(N_LEGS)]
        if not self._t:
            return out
        t = np.fromiter(self._t, dtype=float, count=len(self._t))
        s = np.stack(list(self._s))
        t0 = t[-1] - self.window_s
        ends = np.append(t[1:], t[-1])
        for leg in range(N_LEGS):
            on = s[:, leg]
            start: float | None = None
            for i in range(len(t)):
                if on[i] and start is None:
                    start = t[i]
                if start is not None and (not on[i] or i == len(t) - 1):
                    end = t[i] if not on[i] else ends[i]
                    a, b = max(start, t0), end
                    if b > a:
                        out[leg].append((float(a), float(b)))
                    start = None
        return out


@dataclass(frozen=True)
class D31Event:
    time_s: float
    d31: float
    beta: float
    ramp: str = ""  # "down"/"up" while the beta ramp ran, else ""


class D31Trace:
    """Delta31 at each leg-1 touchdown, with the beta in force then (for the bifurcation panel).

    `sim.d31_events` is the core's full list since the last reset; `sync` takes only what is new,
    so the loop can call it after every chunk of stepping at no cost.
    """

    def __init__(self, maxlen: int = 5_000) -> None:
        self.events: deque[D31Event] = deque(maxlen=maxlen)
        # the latest beta ramp's path (a ramp at the default rate takes ~2 minutes, ~1300 events)
        self.ramp_path: deque[D31Event] = deque(maxlen=20_000)
        self._seen = 0  # how many of the core's events have been taken
        self.version = 0

    def clear(self) -> None:
        self.events.clear()
        self.ramp_path.clear()
        self._seen = 0
        self.version += 1

    def sync(self, core_events: list[tuple[float, float]], beta: float, ramp: str = "") -> int:
        """Take new events from the core's list; returns how many were new.

        `ramp` ("down"/"up"/"") is the beta ramp's direction now; events taken during a ramp
        are also kept in `ramp_path`, the path the ramp draws on the bifurcation panel.
        """
        n = len(core_events)
        if n < self._seen:  # the core started over (reset)
            self._seen = 0
        new = core_events[self._seen :]
        for t, d in new:
            if math.isfinite(d):
                event = D31Event(float(t), float(d), float(beta), ramp)
                self.events.append(event)
                if ramp:
                    self.ramp_path.append(event)
        self._seen = n
        if new:
            self.version += 1
        return len(new)

    def recent(self, since_s: float) -> list[D31Event]:
        return [e for e in self.events if e.time_s >= since_s]

    @property
    def last(self) -> D31Event | None:
        return self.events[-1] if self.events else None

"""Rolling records the panels draw from: stance samples (footfall diagram) and Delta31 events.

The loop samples stance far more often than it redraws (a swing lasts 34 ms, a frame 33 ms), so
the buffers keep raw samples and turn them into bars only when a panel is redrawn. Time going
backwards means the simulation was reset: the record starts over rather than drawing nonsense.
"""

from __future__ import annotations

import bisect
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


# The whole run is kept, up to these caps (then the oldest go): 200 000 touchdowns are ~5.5 h
# of walking at ~10 leg-1 touchdowns per second, 1.2 million stance intervals ~5.5 h of six legs.
MAX_D31_EVENTS = 200_000
MAX_STANCE_INTERVALS = 1_200_000


class StanceLog:
    """Every stance interval of the run, per leg (for export): the footfall diagram's data
    beyond its few-second window. Fed the same samples (one per control period), in bulk."""

    def __init__(self, max_intervals: int = MAX_STANCE_INTERVALS) -> None:
        self.max_intervals = max_intervals
        self.clear()

    def clear(self) -> None:
        self.intervals: list[tuple[int, float, float]] = []  # (leg index, start, end)
        self._open: list[float | None] = [None] * N_LEGS
        self._t_last: float | None = None
        self.dropped = 0

    def extend(self, times: np.ndarray, stance: np.ndarray) -> None:
        """Samples (times (T,), stance (T, 6) bool), later than the last one taken."""
        t = np.asarray(times, dtype=float)
        s = np.asarray(stance, dtype=bool).reshape(-1, N_LEGS)
        if t.size == 0:
            return
        if self._t_last is not None and t[0] < self._t_last:
            self.clear()  # reset
        for leg in range(N_LEGS):
            on = s[:, leg]
            was = self._open[leg] is not None
            prev = np.concatenate([[was], on[:-1]])
            starts = np.flatnonzero(on & ~prev)  # transitions alternate on the leg
            ends = np.flatnonzero(~on & prev)
            if was and ends.size:  # the interval open from before ends first
                start = self._open[leg]
                assert start is not None
                self.intervals.append((leg, start, float(t[ends[0]])))
                self._open[leg] = None
                ends = ends[1:]
            for a, b in zip(starts, ends, strict=False):
                self.intervals.append((leg, float(t[a]), float(t[b])))
            if starts.size > ends.size:
                self._open[leg] = float(t[starts[-1]])
        self._t_last = float(t[-1])
        over = len(self.intervals) - self.max_intervals
        if over > 0:
            del self.intervals[:over]
            self.dropped += over

    def rows(self) -> list[tuple[str, float, float]]:
        """(leg name index order R1 L1 R2 L2 R3 L3 as 0..5, start, end) sorted by start; an
        interval still open ends at the last sample."""
        out = [(leg, a, b) for leg, a, b in self.intervals]
        if self._t_last is not None:
            out += [(leg, a, self._t_last) for leg, a in enumerate(self._open) if a is not None]
        return [(str(leg), a, b) for leg, a, b in sorted(out, key=lambda r: (r[1], r[0]))]


@dataclass(frozen=True)
class D31Event:
    time_s: float
    d31: float
    beta: float
    ramp: str = ""  # "down"/"up"/"hold" while a ramp ran, else ""
    body_mass_g: float = math.nan
    slope_deg: float = math.nan


class D31Trace:
    """Delta31 at each leg-1 touchdown of the whole run (up to MAX_D31_EVENTS), with the beta,
    mass and slope in force then (for the panels and the export).

    `sim.d31_events` is the core's full list since the last reset; `sync` takes only what is new,
    so the loop can call it after every chunk of stepping at no cost.
    """

    def __init__(self, maxlen: int = MAX_D31_EVENTS) -> None:
        self.maxlen = maxlen
        self.events: list[D31Event] = []
        self._times: list[float] = []  # the events' times, for bisection
        # the latest ramp's path (all of it, up to the same cap)
        self.ramp_path: deque[D31Event] = deque(maxlen=maxlen)
        self._seen = 0  # how many of the core's events have been taken
        self.version = 0

    def clear(self) -> None:
        self.events.clear()
        self._times.clear()
        self.ramp_path.clear()
        self._seen = 0
        self.version += 1

    def sync(
        self,
        core_events: list[tuple[float, float]],
        beta: float,
        ramp: str = "",
        body_mass_g: float = math.nan,
        slope_deg: float = math.nan,
    ) -> int:
        """Take new events from the core's list; returns how many were new.

        `ramp` ("down"/"up"/"hold"/"") is the ramp's phase now; events taken during a ramp
        are also kept in `ramp_path`, the path the ramp draws on the bifurcation panel.
        """
        n = len(core_events)
        if n < self._seen:  # the core started over (reset)
            self._seen = 0
        new = core_events[self._seen :]
        for t, d in new:
            if math.isfinite(d):
                event = D31Event(float(t), float(d), float(beta), ramp, body_mass_g, slope_deg)
                self.events.append(event)
                self._times.append(event.time_s)
                if ramp:
                    self.ramp_path.append(event)
        over = len(self.events) - self.maxlen
        if over > 0:
            del self.events[:over]
            del self._times[:over]
        self._seen = n
        if new:
            self.version += 1
        return len(new)

    def recent(self, since_s: float) -> list[D31Event]:
        return self.events[bisect.bisect_left(self._times, since_s) :]

    def last_n(self, n: int) -> list[D31Event]:
        return self.events[-n:] if n > 0 else []

    @property
    def last(self) -> D31Event | None:
        return self.events[-1] if self.events else None

"""What the panels and exports draw, read from the running `Simulation`'s own record.

The simulation keeps the history (`Simulation.footfall_since`: stance at every control period
over its last `history_s` seconds; `Simulation.d31_events`: Delta31 at every leg-1 touchdown
since the last reset), so the viewer keeps no copy of it: the footfall diagram and its export
are computed from the stance record when drawn, and the Delta31 trace, return map and trail
read the core's event list, with what was in force at each event (`Simulation.d31_conditions`:
beta, body mass, slope, ground, the ramp's phase). The viewer adds only the marks it draws
(`D31Conditions`) and where its latest ramp began.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass
from operator import itemgetter
from typing import TYPE_CHECKING, Protocol

import numpy as np

from sim_core.contract import LEG_NAMES, EventConditions

if TYPE_CHECKING:
    from sim_core import Simulation

Interval = tuple[float, float]
CoreEvents = Sequence[tuple[float, float]]  # `Simulation.d31_events`: (time_s, Delta31)


def stance_intervals(times: np.ndarray, stance: np.ndarray) -> list[list[Interval]]:
    """Per leg (paper order), (start, end) of each stance interval in the samples, in time order.

    Sample i stands for [t_i, t_{i+1}); an interval still open at the last sample ends there.
    """
    t = np.asarray(times, dtype=float)
    on = np.asarray(stance, dtype=bool).reshape(-1, len(LEG_NAMES))
    if t.size == 0:
        return [[] for _ in LEG_NAMES]
    edges = np.diff(on.astype(np.int8), axis=0, prepend=0, append=0)  # +1 on, -1 off
    last = t.size - 1
    out = []
    for leg in range(len(LEG_NAMES)):
        starts = np.flatnonzero(edges[:, leg] == 1)
        ends = np.minimum(np.flatnonzero(edges[:, leg] == -1), last)
        out.append(
            [(float(t[a]), float(t[b])) for a, b in zip(starts, ends, strict=True) if t[b] > t[a]]
        )
    return out


def footfall_bars(sim: Simulation, window_s: float) -> list[list[Interval]]:
    """The stance bars of the simulation's last `window_s` seconds (the footfall diagram),
    from samples reaching two control periods before the window, so that the sample in force
    at its edge is among them whatever the rounding of the times: a leg in stance there has a
    bar from the edge (the diagram clips the bars to the window it shows)."""
    return stance_intervals(*sim.footfall_since(sim.time_s - window_s - 2 * sim.control_dt_s))


def d31_since(events: CoreEvents, since_s: float) -> CoreEvents:
    """The core's Delta31 events from `since_s` on (the list is in time order)."""
    return events[bisect.bisect_left(events, since_s, key=itemgetter(0)) :]


@dataclass(frozen=True)
class Mark:
    """A change of conditions on the Delta31 history, at the first event under the new ones."""

    time_s: float
    label: str
    by_person: bool = True  # a parameter set by a person (False: a ramp's phase, never merged)


MARK_MERGE_S = 1.0  # a person's changes closer than this are one mark (a drag, typed digits)
_PARAM_WORDS = (
    ("beta", "β {:.3f}"),
    ("body_mass_g", "mass {:.2f} g"),
    ("slope_deg", "slope {:.1f}°"),
)
_SHORT = {"beta": "β", "body_mass_g": "mass", "slope_deg": "slope"}


def _differs(a: float, b: float) -> bool:
    return not (a == b or (math.isnan(a) and math.isnan(b)))


def change_label(before: EventConditions, now: EventConditions) -> str:
    """What changed between two events' conditions, in a few words ("" if nothing a person
    would mark): a ramp's phase ("ramp β up"), or outside ramps the parameters set."""
    if now.ramp != before.ramp:
        if not now.ramp:
            return "ramp over"
        return f"ramp {_SHORT.get(now.ramp_param, now.ramp_param)} {now.ramp}"
    if now.ramp:
        return ""  # the ramp moves its parameter at every event: only its phases are marks
    words = [
        fmt.format(getattr(now, name))
        for name, fmt in _PARAM_WORDS
        if _differs(getattr(now, name), getattr(before, name))
    ]
    return ", ".join(words)


@dataclass(frozen=True)
class D31Event:
    """One of the core's Delta31 events with the conditions in force then."""

    time_s: float
    d31: float
    at: EventConditions


class EventRecord(Protocol):
    """What the viewer reads of a live run's events (`sim_core.Simulation`)."""

    @property
    def d31_events(self) -> CoreEvents: ...

    @property
    def d31_conditions(self) -> Sequence[EventConditions]: ...


class D31Conditions:
    """The marks on the Delta31 history and where the latest ramp began, over the core's own
    record: the events and what was in force at each (`Simulation.d31_events`,
    `Simulation.d31_conditions`, index for index); this keeps no copy of either."""

    def __init__(self) -> None:
        self._seen = 0  # events whose conditions were read for marks
        self._ramp_from = 0
        self._marks: list[Mark] = []

    def __len__(self) -> int:
        return self._seen

    def clear(self) -> None:
        """The simulation started over (its record with it)."""
        self._seen = 0
        self._ramp_from = 0
        self._marks.clear()

    @property
    def marks(self) -> list[Mark]:
        """Where the conditions changed: a parameter set by a person, a ramp's phase."""
        return list(self._marks)

    def note(self, run: EventRecord) -> None:
        """Marks for the events the core added since the last call (the loop calls this after
        every chunk of stepping): one where the conditions changed from the event before."""
        events, at = run.d31_events, run.d31_conditions
        n = min(len(events), len(at))
        if n < self._seen:  # the core started over without our being told
            self.clear()
        for k in range(max(self._seen, 1), n):
            before, now = at[k - 1], at[k]
            if now == before:
                continue
            label = change_label(before, now)
            if not label:
                continue
            t = events[k][0]
            by_person = not now.ramp and not before.ramp  # not a ramp's phase
            last = self._marks[-1] if self._marks else None
            if by_person and last is not None and last.by_person and t - last.time_s < MARK_MERGE_S:
                self._marks[-1] = Mark(t, label)  # a slider dragged: one mark, its end
            else:
                self._marks.append(Mark(t, label, by_person))
        self._seen = n

    def start_ramp(self, run: EventRecord) -> None:
        """A new ramp begins: its path starts with the next event."""
        self._ramp_from = len(run.d31_events)

    def events(self, run: EventRecord, start: int = 0) -> list[D31Event]:
        """The core's events from index `start` (negative: from the end) with their conditions."""
        core, at = run.d31_events, run.d31_conditions
        n = min(len(at), len(core))
        first = max(0, n + start) if start < 0 else min(start, n)
        return [D31Event(t, d, c) for (t, d), c in zip(core[first:n], at[first:n], strict=True)]

    def ramp_path(self, run: EventRecord) -> list[D31Event]:
        """The latest ramp's events (those taken while it ran), for its drawing and export."""
        return [e for e in self.events(run, self._ramp_from) if e.at.ramp]

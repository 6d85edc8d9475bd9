"""What GUI callbacks may do: record a request. The loop thread alone applies them.

viser runs plain callbacks on a thread pool, and `Simulation` is not thread-safe, so a callback
never touches the simulation; it puts one of these frozen requests on a `RequestQueue`. The loop
drains the queue once per frame. Dragging a slider fires dozens of updates per frame; draining
coalesces them so that only the latest value of each setting is applied (a reset, ramp start or
stop is kept in its place so that "set beta, then reset" still means what it says).
"""

from __future__ import annotations

import queue
from dataclasses import dataclass


@dataclass(frozen=True)
class SetBeta:
    value: float


@dataclass(frozen=True)
class SetBodyMass:
    grams: float


@dataclass(frozen=True)
class SetSlope:
    degrees: float


@dataclass(frozen=True)
class SetSpeed:
    multiplier: float | None  # None: as fast as the machine allows


@dataclass(frozen=True)
class SetPlaying:
    playing: bool


@dataclass(frozen=True)
class SetFollow:
    mode: str  # one of controls.CAMERA_MODES


@dataclass(frozen=True)
class SetFootfallWindow:
    seconds: float


@dataclass(frozen=True)
class Reset:
    d31_init: float


@dataclass(frozen=True)
class StartRamp:
    rate_per_s: float


@dataclass(frozen=True)
class StopRamp:
    pass


Request = (
    SetBeta
    | SetBodyMass
    | SetSlope
    | SetSpeed
    | SetPlaying
    | SetFollow
    | SetFootfallWindow
    | Reset
    | StartRamp
    | StopRamp
)

# Settings: a later one of the same type makes an earlier one pointless.
_SETTINGS = (
    SetBeta,
    SetBodyMass,
    SetSlope,
    SetSpeed,
    SetPlaying,
    SetFollow,
    SetFootfallWindow,
)


def coalesce(requests: list[Request]) -> list[Request]:
    """Drop settings that a later request of the same type overrides, keeping the order.

    A setting is only dropped when no order-sensitive request (reset, ramp start/stop) lies
    between it and its replacement: `SetBeta(0.6), StartRamp, SetBeta(0.7)` must still stop the
    ramp (a manual beta wins over the ramp), while the ramp must start from 0.6.
    """
    out: list[Request] = []
    last_index: dict[type, int] = {}
    for req in requests:
        kind = type(req)
        if isinstance(req, _SETTINGS):
            i = last_index.get(kind)
            if i is not None:
                out[i] = req  # replace in place: nothing order-sensitive came since
                continue
            last_index[kind] = len(out)
            out.append(req)
        else:
            # an order-sensitive request: later settings must not jump over it
            last_index.clear()
            out.append(req)
    return out


class RequestQueue:
    """Thread-safe inbox from GUI callbacks (any thread) to the loop thread (one consumer)."""

    def __init__(self) -> None:
        self._q: queue.SimpleQueue[Request] = queue.SimpleQueue()

    def put(self, request: Request) -> None:
        self._q.put(request)

    def drain(self) -> list[Request]:
        """Everything queued so far, coalesced; never blocks."""
        items: list[Request] = []
        while True:
            try:
                items.append(self._q.get_nowait())
            except queue.Empty:
                return coalesce(items)

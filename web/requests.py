"""What GUI callbacks may do: queue a request. The loop alone applies it (web/handlers.py).

viser runs plain callbacks on a thread pool, and `Simulation` is not thread-safe, so a callback
never touches the simulation; it puts one of these frozen requests on a `RequestQueue`. The loop
drains the queue once per frame. Dragging a slider fires dozens of updates per frame; draining
coalesces them so that only the latest value of each setting is applied (a reset, ramp start or
stop is kept in its place so that "set beta, then reset" still means what it says).
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable
from dataclasses import dataclass, field

from sim_core.contract import Ramp, RampParam
from web.controls import LIVE_NAMES
from web.export import Settings


@dataclass(frozen=True)
class SetParam:
    """Set a live parameter: one of PARAMS (the RunSpec field names `Simulation.set` takes)."""

    name: RampParam
    value: float


PARAMS = LIVE_NAMES


@dataclass(frozen=True)
class SetSpeed:
    multiplier: float | None  # None: as fast as the machine allows


@dataclass(frozen=True)
class SetPlaying:
    playing: bool


@dataclass(frozen=True)
class StepCycle:
    """While paused: walk one gait cycle (T_sw / (1 - beta) at the beta in force), then stop
    again, as a debugger's single step (mujoco's viewer steps one physics step; one cycle is
    the smallest step in which every leg lands once)."""


@dataclass(frozen=True)
class SetFollow:
    mode: str  # one of controls.CAMERA_MODES


@dataclass(frozen=True)
class SetDraw3D:
    """Stream the 3D walk (True) or hold the last pose (False): a browser without a GPU renders
    continuously while poses arrive (viser re-renders for 250 ms after each scene change),
    which takes a core the simulation could use; the plots and readouts stay live."""

    on: bool


@dataclass(frozen=True)
class SetFootfallWindow:
    seconds: float


@dataclass(frozen=True)
class Reset:
    d31_init: float


@dataclass(frozen=True)
class SetGround:
    """Walk on another ground (`ModelParams.ground`): a restart from the last initial Delta31
    at the current beta, mass and slope, so it keeps its place among resets."""

    ground: str


@dataclass(frozen=True)
class StartRamp:
    ramp: Ramp  # the core's schedule; the loop sets the ramped parameter from it


@dataclass(frozen=True)
class StopRamp:
    pass


@dataclass(frozen=True)
class SetD31Window:
    seconds: float | None  # None: the whole run


@dataclass(frozen=True)
class Export:
    """Build a file of `what` (web/export.py) on the loop thread and hand it to `send`
    (the asking browser's download: name, bytes)."""

    what: str
    send: Callable[[str, bytes], None] = field(compare=False, repr=False)


@dataclass(frozen=True)
class SubmitJob:
    """POST the current settings to the API as a job of `kind` ("run", or "hysteresis": the
    ramp set up in the ramp inputs) and follow it (web/jobs.py)."""

    kind: str


@dataclass(frozen=True)
class SubmitSurface:
    """POST a `surface` job for the walk's ground, mass and slope and draw its result on the
    drift-surface panel when it is done (web/surface_jobs.py)."""


@dataclass(frozen=True)
class OpenJob:
    """Follow an existing job of any kind by its id: its progress, then its figure."""

    job_id: str


@dataclass(frozen=True)
class CancelJob:
    """Ask the API to cancel job `key` of this viewer's list (web/jobs.py)."""

    key: int


@dataclass(frozen=True)
class ReplayJob:
    """Draw done job `key`'s run in the Delta31, footfall and ramp-path panels instead of the
    live walk's, until `StopReplay` (web/job_replay.py)."""

    key: int


@dataclass(frozen=True)
class StopReplay:
    """The panels draw the live walk again."""


@dataclass(frozen=True)
class LoadSettings:
    """Walk at the settings of an exported settings file (`export.load_settings`): its ground,
    beta, mass and slope, speed and initial Delta31 (a restart), its ramp in the ramp inputs."""

    settings: Settings = field(compare=False)


Request = (
    SetParam
    | SetSpeed
    | SetPlaying
    | StepCycle
    | SetFollow
    | SetDraw3D
    | SetFootfallWindow
    | Reset
    | SetGround
    | SetD31Window
    | StartRamp
    | StopRamp
    | Export
    | SubmitJob
    | SubmitSurface
    | OpenJob
    | CancelJob
    | ReplayJob
    | StopReplay
    | LoadSettings
)

# Settings: a later one of the same type makes an earlier one pointless.
_SETTINGS = (
    SetParam,
    SetDraw3D,
    SetSpeed,
    SetPlaying,
    SetFollow,
    SetFootfallWindow,
    SetD31Window,
)


def _key(req: Request) -> tuple[type, str]:
    """What a later setting replaces: the same type (and, for SetParam, the same parameter)."""
    return (type(req), req.name if isinstance(req, SetParam) else "")


def coalesce(requests: list[Request]) -> list[Request]:
    """Drop settings that a later request of the same type overrides, keeping the order.

    A setting is only dropped when no order-sensitive request (reset, ramp start/stop, export)
    lies between it and its replacement: in `SetParam("beta", 0.6), StopRamp,
    SetParam("beta", 0.7)` both betas are applied, in their places.
    """
    out: list[Request] = []
    last_index: dict[tuple[type, str], int] = {}
    for req in requests:
        kind = _key(req)
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
        self._arrived = threading.Event()  # wakes the loop: a request is applied when it comes

    def put(self, request: Request) -> None:
        self._q.put(request)
        self._arrived.set()

    def pending(self) -> bool:
        """Whether a request waits (the loop stops stepping between slices to apply it)."""
        return not self._q.empty()

    def wait(self, timeout_s: float) -> bool:
        """Sleep until a request arrives or `timeout_s` passes; True if one arrived."""
        arrived = self._arrived.wait(max(0.0, timeout_s))
        self._arrived.clear()
        return arrived or self.pending()

    def drain(self) -> list[Request]:
        """Everything queued so far, coalesced; never blocks."""
        items: list[Request] = []
        while True:
            try:
                items.append(self._q.get_nowait())
            except queue.Empty:
                return coalesce(items)

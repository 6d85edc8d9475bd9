"""A parameter ramped during a run: the paper's quasi-static sweeps (Figs. 6a, 9).

The one definition of the sweep schedule (hold, ramp to the turn, ramp back, hold), of its
phases, and of how a ramped value reaches a running simulation (`RampDriver`), shared by the
reproduction's tasks, the public `sweep` (which the REST API's hysteresis jobs call) and the
live `Simulation` (the viewer's ramps); and what a live run records at each Delta31 event
(`EventConditions`). MuJoCo-free: the API validates sweeps with it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:  # the schedule itself needs no MuJoCo: the API validates sweeps with it
    from sim_core.model.runner import BatchRunner

RampParam = Literal["beta", "body_mass_g", "slope_deg"]
RAMP_PARAMS: tuple[RampParam, ...] = ("beta", "body_mass_g", "slope_deg")
# How often a running ramp updates its parameter, s: a tenth of a stride at beta 0.66 (T ~ 0.1
# s); a 30 s ramp of beta over 0.08 then moves in steps of 2.7e-5, far below any effect we
# measure.
RAMP_UPDATE_S = 0.01


def set_ramped(runner: BatchRunner, index: int, param: str, value: float) -> None:
    """Set simulation `index`'s `param` (beta, g or degrees) between control periods, with
    the runner's own setter (`set_beta`, `set_body_mass_g`, `set_slope_deg`)."""
    if param not in RAMP_PARAMS:
        raise ValueError(f"cannot ramp {param!r}; choose from {list(RAMP_PARAMS)}")
    getattr(runner, f"set_{param}")(index, value)


@dataclass(frozen=True)
class EventConditions:
    """What was in force when a live run's Delta31 event happened (`Simulation.d31_conditions`):
    the parameters, the ground, and the ramp's phase and parameter while a ramp ran."""

    beta: float
    body_mass_g: float
    slope_deg: float
    ground: str = "constraint"
    ramp: str = ""  # "hold", "down" or "up" while a ramp ran, else ""
    ramp_param: str = ""  # the parameter that ramp moved, else ""


@dataclass(frozen=True)
class Ramp:
    """A triangle schedule: hold `start`, ramp to `turn` in `ramp_s`, back in `ramp_s`, hold.

    Values in the units of the RunSpec field being ramped (beta, g, degrees)."""

    param: RampParam
    start: float
    turn: float
    hold_s: float
    ramp_s: float

    @property
    def duration_s(self) -> float:
        return 2.0 * self.hold_s + 2.0 * self.ramp_s

    @property
    def turn_time_s(self) -> float:
        return self.hold_s + self.ramp_s

    def schedule(self) -> Callable[[float], float]:
        return self.value

    def phase(self, t: float) -> str:
        """'hold', 'down' or 'up' (the way the value moves) at time t (s), 'done' after it."""
        if t >= self.duration_s:
            return "done"
        if t < self.hold_s or t >= self.turn_time_s + self.ramp_s:
            return "hold"
        towards = "up" if self.turn > self.start else "down"
        if t < self.turn_time_s:
            return towards
        return "down" if towards == "up" else "up"

    def value(self, t: float) -> float:
        """The ramped value at time t (s): the Fig. 6a protocol."""
        if t < self.hold_s:
            return self.start
        u = t - self.hold_s
        if u < self.ramp_s:
            return self.start + (self.turn - self.start) * u / self.ramp_s
        u -= self.ramp_s
        if u < self.ramp_s:
            return self.turn + (self.start - self.turn) * u / self.ramp_s
        return self.start


class RampDriver:
    """The one way ramps reach running simulations: a run loop's hook (`BatchRunner.run`) that
    sets each ramped run's value for the coming control period every `RAMP_UPDATE_S`, from its
    ramp's clock (`t0`: the runner's time at which the ramp began). The reproduction's tasks,
    `sweep` (through them) and the live `Simulation` (the viewer) all ramp with it."""

    def __init__(
        self,
        ramps: Sequence[tuple[int, Ramp]],
        control_dt: float,
        t0: float = 0.0,
        start_block: int = 0,
    ) -> None:
        self.ramps = list(ramps)
        self.t0 = t0
        # updates every `every` control periods counted from the ramp's own start (the runner's
        # block count then), so its first call sets the start value whenever it begins
        self.start_block = start_block
        self.every = max(1, round(RAMP_UPDATE_S / control_dt))
        self._last = [math.nan] * len(self.ramps)

    def __call__(self, r: BatchRunner) -> None:
        """Each ramped run's value for the coming control period (every RAMP_UPDATE_S)."""
        if (r.nblock - self.start_block) % self.every:
            return
        for k, (i, ramp) in enumerate(self.ramps):
            if r.active[i]:
                v = float(ramp.value(r.time - self.t0))
                if v != self._last[k]:
                    set_ramped(r, i, ramp.param, v)
                    self._last[k] = v

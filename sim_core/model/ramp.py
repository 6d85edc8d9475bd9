"""A parameter ramped during a run: the paper's quasi-static sweeps (Figs. 6a, 9).

The one definition of the sweep schedule (hold, ramp to the turn, ramp back, hold) and of how
a ramped value reaches a running simulation, shared by the reproduction's tasks and the public
`sweep` (which the REST API's hysteresis jobs call). The viewer's demo ramp is another schedule
on purpose (`web/controls.BetaRamp`: down to the slider's low end, up to its top, back to where
the person stood), because it draws a whole loop from any starting beta.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:  # the schedule itself needs no MuJoCo: the API validates sweeps with it
    from sim_core.model.runner import BatchRunner

RampParam = Literal["beta", "body_mass_g", "slope_deg"]
RAMP_PARAMS: tuple[RampParam, ...] = ("beta", "body_mass_g", "slope_deg")


def set_ramped(runner: BatchRunner, index: int, param: str, value: float) -> None:
    """Set simulation `index`'s `param` (beta, g or degrees) between control periods, with
    the runner's own setter (`set_beta`, `set_body_mass_g`, `set_slope_deg`)."""
    if param not in RAMP_PARAMS:
        raise ValueError(f"cannot ramp {param!r}; choose from {list(RAMP_PARAMS)}")
    getattr(runner, f"set_{param}")(index, value)


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

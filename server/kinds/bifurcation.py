"""`bifurcation`: the paper's Fig. 8 over a beta grid from settled walking, by the fixed-point
finder (`insect-gait finder`), the drift surface's independent check."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field

from server.kinds.base import BetaRange, Kind, Result
from server.kinds.bounds import DURATION_BOUNDS, IntLike, bounded
from server.kinds.common import conditions, d31_axis, paper_ranges, paper_transitions
from server.kinds.compute import Compute
from server.kinds.finder import (
    FINDER_DEFAULTS,
    Finder,
    FinderRow,
    draw_finder_points,
    finder_rows,
    finder_runner,
)
from sim_core import find
from sim_core.contract import TWO_PI, Cell, FinderConfig, FinderOutput

if TYPE_CHECKING:
    from matplotlib.figure import Figure


# For the cost estimate only (the bounds and eta): states per beta kicked, and neighbours'
# states that the spread starts miss, as measured on the default model at beta 0.62-0.70.
KICKED_STATES = 3
NEIGHBOUR_SEEDS = 2


class BifurcationJob(Finder):
    """The paper's Fig. 8 over a beta grid, from settled walking (the fixed-point finder, the
    same function as `insect-gait reproduce`): stable gaits with how many starts reach them
    and their map slope, unstable ones as bisected basin borders, ghosts, and the runs that
    did not settle in the time given."""

    kind: Literal["bifurcation"] = "bifurcation"
    beta_range: BetaRange
    bisect_duration_s: float = bounded(
        FINDER_DEFAULTS.bisect_duration_s, "bisect_duration_s",
        "simulated time of a bisection run, s (re-run at duration_s if it has not settled)",
        ge=2.0, le=DURATION_BOUNDS["le"],
    )  # fmt: skip
    border_tol_rad: float = bounded(
        FINDER_DEFAULTS.border_tol_rad, "border_tol_rad",
        "width of a bisected border's bracket, rad", ge=0.005, le=1.0,
    )  # fmt: skip
    max_borders: IntLike = bounded(
        FINDER_DEFAULTS.max_borders, "max_borders", "basin borders bisected per beta", ge=0, le=4
    )
    kick_rad: float = bounded(
        FINDER_DEFAULTS.kick_rad, "kick_rad",
        "each state is re-run from this far on either side and counts as stable only if both "
        "come back, rad (0: no kicks, states reported as not checked)", ge=0.0, le=0.3,
    )  # fmt: skip
    neighbour_seeds: bool = FINDER_DEFAULTS.neighbour_seeds

    def cells(self) -> int:
        return self.beta_range.steps

    def bisect_steps(self) -> int:
        """Bisection runs one border may take: from the starts' spacing to border_tol_rad."""
        return max(1, math.ceil(math.log2(TWO_PI / self.starts / self.border_tol_rad)))

    def kick_runs(self) -> int:
        """Kick runs per beta, estimated: two per state, about 3 states per beta measured."""
        return 2 * KICKED_STATES if self.kick_rad > 0 else 0

    def seed_runs(self) -> int:
        """Neighbour seeds per beta, estimated: about 2 states the spread starts miss."""
        return NEIGHBOUR_SEEDS if self.neighbour_seeds and self.cells() > 1 else 0

    def extra_runs_per_cell(self) -> int:
        return self.max_borders * self.bisect_steps() + self.kick_runs() + self.seed_runs()

    def extra_sim_seconds_per_cell(self) -> float:
        bisect_and_kicks = self.max_borders * self.bisect_steps() + self.kick_runs()
        return bisect_and_kicks * self.bisect_duration_s + self.seed_runs() * self.duration_s

    def finder_config(self) -> FinderConfig:
        return FinderConfig(
            starts=self.starts, duration_s=self.duration_s,
            bisect_duration_s=self.bisect_duration_s, border_tol_rad=self.border_tol_rad,
            max_borders=self.max_borders, kick_rad=self.kick_rad,
            neighbour_seeds=self.neighbour_seeds,
        )  # fmt: skip


class BifurcationJobResult(Result):
    """A bifurcation job's result: the finder's typed output and one row per point."""

    kind: Literal["bifurcation"] = "bifurcation"
    records: list[FinderRow]
    finder: FinderOutput = Field(description="the settled fixed-point finder's output")


def run(job: BifurcationJob, compute: Compute) -> BifurcationJobResult:
    """Fig. 8 from settled walking: the fixed-point finder (`find`, the function `reproduce`
    uses) at every beta of the grid, its runs through the shared cache; its typed output
    (`FinderOutput`) plus flat rows."""
    held = job.spec()  # the job's template, typed: its mass and slope are each cell's
    cells = [Cell(beta=b, body_mass_g=held.body_mass_g, slope_deg=held.slope_deg)
             for b in job.beta_range.values()]  # fmt: skip
    found = find(cells, job.finder_config(), finder_runner(job, compute))
    out = FinderOutput(source="REST bifurcation job: the settled fixed-point finder",
                       config=job.finder_config(), cells=found)  # fmt: skip
    return BifurcationJobResult(finder=out, records=finder_rows(found))


def draw(fig: Figure, spec: dict[str, Any], result: dict[str, Any]) -> None:
    """The finder's states over beta (the paper's Fig. 8), with the paper's stable ranges and
    transition betas beside them."""
    ax = fig.add_subplot()
    paper_ranges(ax)
    paper_transitions(ax)
    draw_finder_points(ax, result.get("records", []))
    ax.set_xlabel("duty factor β")
    ax.set_ylabel("Δ31 at leg-1 touchdown (rad)")
    d31_axis(ax)
    ax.set_title(f"bifurcation: settled states over β{conditions(spec)}", fontsize="medium")
    ax.legend(fontsize="x-small", loc="upper left")
    ax.grid(alpha=0.3)


KIND = Kind(model=BifurcationJob, run=run, result=BifurcationJobResult, row=FinderRow, draw=draw)

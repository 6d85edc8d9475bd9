"""`atlas`: which gaits are stable over beta x body mass or beta x slope, on a small grid, by the
function `insect-gait atlas` uses."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import Field, ValidationInfo, field_validator

from server.kinds.base import Kind, Progress
from server.kinds.bounds import (
    DURATION_BOUNDS,
    SWEEP_RANGES,
    IntLike,
    bounded,
    in_range,
    range_text,
)
from server.kinds.common import core
from server.kinds.finder import (
    FINDER_COLUMNS,
    Finder,
    draw_finder_points,
    finder_rows,
    finder_runner,
)
from sim_core.contract import AXIS_PARAM, AtlasAxis, AtlasOutput, region_of

if TYPE_CHECKING:
    from matplotlib.figure import Figure


class AtlasJob(Finder):
    """The gait atlas on a small grid: which gaits are stable over beta x body mass or beta x
    slope (the same function as `insect-gait atlas`), each cell seeded with its neighbours'
    attractors; no bisection."""

    kind: Literal["atlas"] = "atlas"
    axis: AtlasAxis = Field(
        "mass", description="the second axis: mass (body_mass_g) or slope (slope_deg)",
        json_schema_extra={"allowed": "mass, slope"},
    )  # fmt: skip
    betas: list[Annotated[float, Field(gt=0.5, lt=1.0, allow_inf_nan=False)]] = Field(
        [0.62, 0.70], min_length=1, max_length=8,
        description="duty factors of the grid (1-8 values)",
    )  # fmt: skip
    values: list[Annotated[float, Field(allow_inf_nan=False)]] = Field(
        [2.0, 5.0], min_length=1, max_length=8,
        description="values of the axis (g for mass, deg for slope; 1-8 values)",
    )  # fmt: skip
    starts: IntLike = bounded(4, "starts", "starts spread over the circle per cell", ge=2, le=16)
    duration_s: float = bounded(
        30.0, "duration_s", "simulated time of each run, s", ge=2.0, le=DURATION_BOUNDS["le"]
    )

    @field_validator("values")
    @classmethod
    def _in_the_axis_range(cls, v: list[float], info: ValidationInfo) -> list[float]:
        axis = info.data.get("axis")
        if axis is None:
            return v
        param = AXIS_PARAM[axis]
        bounds = SWEEP_RANGES[param]
        for x in v:
            if not in_range(x, bounds):
                raise ValueError(f"{x:g} is outside the range of {param}: "
                                 f"{range_text(param, **bounds)}")  # fmt: skip
        return v

    def cells(self) -> int:
        return len(self.betas) * len(self.values)

    def extra_runs_per_cell(self) -> int:
        return 3  # seeds: at most the attractors of three neighbours, one per place (~1-3)

    def extra_sim_seconds_per_cell(self) -> float:
        return self.extra_runs_per_cell() * self.duration_s


def run(job: AtlasJob, progress: Progress, nthread: int) -> dict[str, Any]:
    """The gait atlas on the job's grid: `atlas_search`, the function `insect-gait atlas`
    uses; its typed output (`AtlasOutput`) plus flat rows with each cell's region."""
    sim = core()
    finder = replace(sim.AtlasConfig(job.axis).finder, starts=job.starts,
                     duration_s=job.duration_s)  # fmt: skip
    cfg = sim.AtlasConfig(job.axis, betas=tuple(job.betas), values=tuple(job.values),
                          finder=finder)  # fmt: skip
    atlas: AtlasOutput = sim.atlas_search(cfg, finder_runner(sim, job, progress, nthread))
    rows = finder_rows(atlas.cells)
    regions = {(c.beta, c.body_mass_g, c.slope_deg): region_of(c) for c in atlas.cells}
    for r in rows:
        r["region"] = regions[(r["beta"], r["body_mass_g"], r["slope_deg"])]
    return {"kind": "atlas", "atlas": atlas.model_dump(mode="json"), "records": rows}


def draw(fig: Figure, spec: dict[str, Any], result: dict[str, Any]) -> None:
    """The finder's points of every cell against beta."""
    ax = fig.add_subplot()
    draw_finder_points(ax, result.get("records", []))
    ax.grid(alpha=0.3)


KIND = Kind(model=AtlasJob, run=run, columns=(*FINDER_COLUMNS, "region"), draw=draw)

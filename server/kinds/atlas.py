"""`atlas`: which gaits are stable over beta x body mass or beta x slope, read from a drift
surface at each value of the axis (`sim_core.surface_atlas`, the function `insect-gait atlas`
and the viewer's atlas panel use): per cell the stable zeros in the paper's window and what
they make of the two gaits, and where each branch folds."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import Field, ValidationInfo, field_validator

import sim_core
from server.kinds.base import Kind, Result, Row
from server.kinds.bounds import SWEEP_RANGES, in_range, range_text
from server.kinds.common import paper_transitions
from server.kinds.compute import Compute
from server.kinds.surface import Held
from sim_core.contract import AXIS_PARAM, AtlasAxis, SurfaceAtlas, SurfaceConfig

if TYPE_CHECKING:
    from matplotlib.figure import Figure


class AtlasRow(Row):
    """One (beta, value) cell of the atlas."""

    beta: float = Field(description="duty factor")
    axis: AtlasAxis = Field(description="the second axis: mass or slope")
    value: float = Field(description="its value (g for mass, deg for slope)")
    region: str = Field(description="what the stable states make of the two gaits")
    stable_d31: str = Field(description="the stable states' Delta31, rad, space-separated")
    gaits: str = Field(description="their gaits, space-separated")
    unresolved: int = Field(description="zeros or near-zero bands left unresolved here")
    undecided: bool = Field(description="an unresolved zero could change the region")
    found_by: str = Field(description="what found the stable states (surface, walks)")


class AtlasJob(Held):
    """The gait atlas from the drift surface: a surface over `betas` at each of `values` of
    the axis (the other held at the job's body_mass_g or slope_deg), read as regions (both /
    tripod only / metachronal only / other states / none) and folds."""

    kind: Literal["atlas"] = "atlas"
    axis: AtlasAxis = Field(
        "mass", description="the second axis: mass (body_mass_g) or slope (slope_deg)",
        json_schema_extra={"allowed": "mass, slope"},
    )  # fmt: skip
    betas: list[Annotated[float, Field(gt=0.5, lt=1.0, allow_inf_nan=False)]] = Field(
        [0.62, 0.70], min_length=1, max_length=25,
        description="duty factors of the grid (1-25 values)",
    )  # fmt: skip
    values: list[Annotated[float, Field(allow_inf_nan=False)]] = Field(
        [2.0, 5.0], min_length=1, max_length=16,
        description="values of the axis (g for mass, deg for slope; 1-16 values)",
    )  # fmt: skip

    band_pass: bool = Field(
        False,
        description="with refine, also probe finer and longer inside unresolved zeros and "
        "near-zero bands (as `insect-gait atlas --band-pass`; about 40% more simulated time)",
    )

    walks: bool = Field(
        True,
        description="decide by settled free walks every cell where an unresolved zero could "
        "change the region, and walk every cell from the paper's start of each gait a "
        "neighbouring cell holds and it lacks (as `insect-gait atlas`; false: as `--no-walks`, "
        "such cells are marked unresolved)",
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

    def config(self) -> SurfaceConfig:
        from dataclasses import replace

        return replace(super().config(), band_pass=self.band_pass)

    def run_count(self) -> int:
        return len(self.betas) * len(self.values) * len(self.config().d31_grid)

    def varied_conditions(self) -> tuple[str, ...]:
        """The axis's field is each row's `value`, not the job's."""
        return (AXIS_PARAM[self.axis],)


class AtlasJobResult(Result):
    """An atlas job's result: the core's typed atlas and one row per (beta, value)."""

    kind: Literal["atlas"] = "atlas"
    records: list[AtlasRow]
    atlas: SurfaceAtlas = Field(description="the gait atlas read from drift surfaces")


def run(job: AtlasJob, compute: Compute) -> AtlasJobResult:
    """The atlas by the core's `surface_atlas`, its probes and walks through the shared cache
    (the keys of `insect-gait atlas`), with one flat row per (beta, value)."""
    sim = sim_core
    moving = compute.moving(job.run_count())  # moves inside each chunk of probes run here
    atlas = sim.surface_atlas(
        job.axis, sorted(set(job.betas)), sorted(set(job.values)), config=job.config(),
        params=job.model_params(), template=job.template(), refine=job.refine,
        walks=sim.WalkConfig() if job.walks else None, progress=False,
        on_progress=moving.on_progress, **compute.core(moving),
    )  # fmt: skip
    rows = [
        {"beta": p.beta, "axis": job.axis, "value": p.value, "region": p.region,
         "stable_d31": " ".join(f"{x:.3f}" for x in p.stable), "gaits": " ".join(p.gaits),
         "unresolved": p.unresolved, "undecided": p.undecided,
         "found_by": " ".join(p.provenance)}
        for p in atlas.points
    ]  # fmt: skip
    return AtlasJobResult(atlas=atlas, records=rows)


def draw(fig: Figure, spec: dict[str, Any], result: dict[str, Any]) -> None:
    """The regions as coloured cells over (beta, value)."""
    from sim_core.contract import AXIS_LABEL, REGION_COLOURS

    ax = fig.add_subplot()
    rows = result.get("records", [])
    for r in rows:
        ax.scatter(r["beta"], r["value"], s=160, marker="s",
                   color=REGION_COLOURS.get(r["region"], "0.8"))  # fmt: skip
    for name, colour in REGION_COLOURS.items():
        ax.scatter([], [], marker="s", color=colour, label=name)
    paper_transitions(ax)
    ax.set_xlabel("duty factor β")
    ax.set_ylabel(AXIS_LABEL.get(spec.get("axis", "mass"), ""))
    ax.set_title("gait atlas from the drift surface")
    ax.legend(fontsize="small", loc="best")


KIND = Kind(model=AtlasJob, run=run, result=AtlasJobResult, row=AtlasRow, draw=draw)

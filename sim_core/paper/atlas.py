"""The gait atlas: the settled fixed-point finder over beta x body mass and beta x slope.

For each cell of the grid: which attractors exist (tripod only / both / metachronal only /
other states, with values), and, along each row, where each gait's stable range ends (the fold
lines). Costs are kept down the way the issue asks: the grid is walked one value row at a time
(every beta of a row in one batch), and each cell also starts from the attractors its
neighbours in the previous row reached (`Cell.seeds`): an attractor that still exists keeps
such a start at once, and one that is gone shows itself by the start leaving. Basin borders are
not bisected here (Fig. 8 does that at body mass 3 g, slope 0): the atlas's borders are the
fold lines between regions.

Every run goes through the result cache on the given backend (local pool or Dask), so an
interrupted atlas resumes where it stopped.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from sim_core.contract.finder import (
    AXIS_LABEL,
    AXIS_PARAM,
    REGIONS,
    AtlasFold,
    AtlasGrid,
    AtlasOutput,
    Cell,
    CellResult,
    FinderConfig,
    RunFn,
    region_of,
)
from sim_core.contract.results import AtlasAxis, atlas_file
from sim_core.model.gait import angle_diff
from sim_core.model.params import ModelParams
from sim_core.paper.analysis import branch_ranges
from sim_core.paper.figures import ReproduceConfig
from sim_core.paper.finder import find
from sim_core.paper.search import task_runner
from sim_core.runs.backends import Backend, RunStats
from sim_core.runs.cache import ResultCache

# 5 betas across both folds of the paper (0.645 / 0.67) and past them
ATLAS_BETAS = (0.60, 0.63, 0.66, 0.69, 0.72)
ATLAS_VALUES: dict[str, tuple[float, ...]] = {
    "mass": (1.0, 2.0, 3.0, 5.0, 8.0, 12.0),  # Table I's 3 g inside; light to heavy, g
    "slope": (-30.0, -15.0, 0.0, 15.0, 30.0),  # downhill to uphill, deg
}
PAPER_DIRECTION = {
    "mass": "paper (Fig. 9a): heavier → tripod, lighter → metachronal, with hysteresis",
    "slope": "paper (Fig. 9b): uphill → tripod, downhill → metachronal, with hysteresis",
}
# 4 spread starts + the neighbours' attractors, 30 s each, no bisection and no kicks (see
# AtlasConfig): the atlas seeds from the previous row itself, and kicks would double its cost
# (~60 min on 2 cores today), so its states are reported as "not checked"
ATLAS_FINDER = FinderConfig(starts=4, duration_s=30.0, max_borders=0, kick_rad=0.0,
                            neighbour_seeds=False)  # fmt: skip
# the paper's Fig. 9 sweeps (ours: `ReproduceConfig`), drawn on the atlas
SWEEP_BETA = ReproduceConfig().sweep_beta
SWEEP_RANGE = {"mass": ReproduceConfig().mass_range_g, "slope": ReproduceConfig().slope_range_deg}
# Seeds closer than this to one already taken are dropped (rad): the same attractor.
SEED_MERGE = 0.1


@dataclass(frozen=True)
class AtlasConfig:
    """Grid and finder settings of one atlas."""

    axis: AtlasAxis
    betas: tuple[float, ...] = ATLAS_BETAS
    values: tuple[float, ...] = ()
    # 4 spread starts + the neighbours' attractors, 30 s each, no bisection: measured at beta
    # 0.62-0.70 (docs/NUMERICS.md, "The finder"), attractors settle by the rule within 13-30 s;
    # a slide slower than 0.2 mrad per cycle at 30 s is listed as not settled
    finder: FinderConfig = field(default_factory=lambda: ATLAS_FINDER)

    def __post_init__(self) -> None:
        if not self.values:
            object.__setattr__(self, "values", ATLAS_VALUES[self.axis])

    @classmethod
    def quick(cls, axis: AtlasAxis) -> AtlasConfig:
        """The machinery on a 2 x 2 grid of short runs (tests, --quick): not science."""
        v = ATLAS_VALUES[axis]
        fc = replace(FinderConfig.quick(), max_borders=0)
        return cls(axis, betas=(0.62, 0.70), values=(v[0], v[-1]), finder=fc)


def _cell(axis: str, beta: float, value: float, seeds: tuple[float, ...] = ()) -> Cell:
    fields: dict[str, Any] = {AXIS_PARAM[axis]: value}
    return Cell(beta=beta, seeds=seeds, **fields)


def _seeds(prev: list[CellResult], j: int) -> tuple[float, ...]:
    """Attractors of the previous row at this beta and its neighbours, one per place."""
    out: list[float] = []
    for k in (j, j - 1, j + 1):
        if 0 <= k < len(prev):
            for a in prev[k].attractors:
                if all(abs(float(angle_diff(a.d31, s))) > SEED_MERGE for s in out):
                    out.append(a.d31)
    return tuple(out)


def atlas_folds(cfg: AtlasConfig, rows: list[list[CellResult]]) -> list[AtlasFold]:
    out: list[AtlasFold] = []
    for value, row in zip(cfg.values, rows, strict=True):
        for gait in ("tripod", "metachronal"):
            for f in branch_ranges(row, gait)["folds"]:
                out.append(AtlasFold(gait=gait, value=value, side=f["side"], beta=f["beta"],
                                     half_width=f["half_width"]))  # fmt: skip
    return out


def atlas_search(cfg: AtlasConfig, run: RunFn, *, log: Any = None) -> AtlasOutput:
    """The atlas of `cfg.axis` with the finder's runs done by `run` (cached tasks for the
    command, `simulate_batch` in an API worker): row by row of the axis, all betas of a row
    in one search, each cell seeded with its neighbours' attractors from the row before."""
    rows: list[list[CellResult]] = []
    for i, value in enumerate(cfg.values):
        seeds = [_seeds(rows[-1], j) if rows else () for j in range(len(cfg.betas))]
        cells = [_cell(cfg.axis, b, value, s) for b, s in zip(cfg.betas, seeds, strict=True)]
        if log is not None:
            log(f"atlas {cfg.axis}: row {i + 1}/{len(cfg.values)} ({AXIS_PARAM[cfg.axis]} = "
                f"{value:g}), {len(cells)} cells")  # fmt: skip
        rows.append(find(cells, cfg.finder, run))
    rng = SWEEP_RANGE[cfg.axis]
    return AtlasOutput(
        source=f"python -m lab finder-atlas --axis {cfg.axis}: the settled fixed-point finder",
        axis=cfg.axis, param=AXIS_PARAM[cfg.axis], betas=list(cfg.betas),
        values=list(cfg.values), cells=[c for row in rows for c in row],
        regions=[[region_of(c) for c in row] for row in rows], folds=atlas_folds(cfg, rows),
        sweep_beta=SWEEP_BETA, sweep_range=rng, paper_direction=PAPER_DIRECTION[cfg.axis],
        config=AtlasGrid(betas=list(cfg.betas), values=list(cfg.values), finder=cfg.finder),
    )  # fmt: skip


def run_atlas(
    cfg: AtlasConfig,
    cache: ResultCache,
    backend: Backend,
    params: ModelParams | None = None,
    *,
    progress: bool = True,
    stats: RunStats | None = None,
) -> AtlasOutput:
    """`atlas_search` with every run cached and on `backend` (an interrupted atlas resumes)."""
    run = task_runner(cache, backend, params, progress=progress, stats=stats)
    return atlas_search(cfg, run, log=print if progress else None)


REGION_COLOURS = {
    "both": "#9ecae1",
    "tripod only": "#fdae6b",
    "metachronal only": "#a1d99b",
    "other states": "#d9d9d9",
    "not settled": "#ffffff",
}


def _short(c: CellResult) -> str:
    """'T 2.95 / M 1.77, 2.12' etc.: each attractor's gait initial and value."""
    tag = {"tripod": "T", "metachronal": "M", "other": "o"}
    parts = [
        f"{tag.get(a.gait, '?')}{a.d31:.2f}" for a in sorted(c.attractors, key=lambda a: a.d31)
    ]
    if c.unsettled:
        parts.append(f"~{len(c.unsettled)}")
    return "\n".join(parts) or "—"


def plot_atlas(out: AtlasOutput, path: Path) -> None:
    """Regions shaded, attractors written in each cell, fold lines, the Fig. 9 sweep path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch, Rectangle

    nb, nv = len(out.betas), len(out.values)
    fig, ax = plt.subplots(figsize=(1.7 * nb + 2.5, 0.95 * nv + 2.2))
    for i in range(nv):
        for j in range(nb):
            c = out.cell(i, j)
            ax.add_patch(
                Rectangle((j - 0.5, i - 0.5), 1, 1, color=REGION_COLOURS[out.regions[i][j]])
            )
            ax.text(j, i, _short(c), ha="center", va="center", fontsize=6.5)

    # fold lines in grid coordinates: beta -> fractional column index
    def col(beta: float) -> float:
        bs = out.betas
        for k in range(nb - 1):
            if bs[k] <= beta <= bs[k + 1]:
                return k + (beta - bs[k]) / (bs[k + 1] - bs[k])
        return float(nb - 1)

    # each fold where it was measured: a bar across its own row at the fold's beta, midway
    # between the two grid betas it lies between (+- half the step); rows are not joined
    for f in out.folds:
        i = out.values.index(f.value)
        colour = "tab:orange" if f.gait == "tripod" else "tab:green"
        ax.plot([col(f.beta)] * 2, [i - 0.5, i + 0.5], "-" if f.side == "upper" else "--",
                color=colour, lw=2.5)  # fmt: skip
    for gait, colour in (("tripod", "tab:orange"), ("metachronal", "tab:green")):
        for side, ls in (("upper", "-"), ("lower", "--")):
            ax.plot([], [], ls, color=colour, lw=2.5,
                    label=f"{gait} fold ({'lives below' if side == 'upper' else 'lives above'} "
                    "this β)")  # fmt: skip
    # the paper's Fig. 9 sweep: at sweep_beta over sweep_range
    lo, hi = out.sweep_range

    def row(v: float) -> float:
        vs = out.values
        for k in range(nv - 1):
            if vs[k] <= v <= vs[k + 1]:
                return k + (v - vs[k]) / (vs[k + 1] - vs[k])
        return 0.0 if v < vs[0] else float(nv - 1)

    x = col(out.sweep_beta)
    ax.annotate("", (x, row(hi)), (x, row(lo)),
                arrowprops={"arrowstyle": "<->", "color": "tab:red", "lw": 1.5})  # fmt: skip
    ax.text(x + 0.05, row(hi), " Fig. 9 sweep", color="tab:red", fontsize=7, va="bottom")
    ax.set_xticks(range(nb), [f"{b:g}" for b in out.betas])
    ax.set_yticks(range(nv), [f"{v:g}" for v in out.values])
    ax.set_xlim(-0.5, nb - 0.5)
    ax.set_ylim(-0.5, nv - 0.5)
    ax.set_xlabel("duty factor β (fast ←  → slow)")
    ax.set_ylabel(AXIS_LABEL[out.axis])
    handles = [Patch(color=REGION_COLOURS[r], label=r) for r in REGIONS]
    h2, _ = ax.get_legend_handles_labels()
    ax.legend(handles=handles + h2, fontsize=6.5, loc="upper left", bbox_to_anchor=(1.01, 1))
    ax.set_title(f"gait atlas: stable gaits over β × {AXIS_LABEL[out.axis]} (settled runs; "
                 "T tripod, M metachronal, o other, ~n not settled)\n" + out.paper_direction,
                 fontsize=8)  # fmt: skip
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def write_atlas(out: AtlasOutput, folder: Path) -> list[Path]:
    """atlas_<axis>.json (the AtlasOutput) and atlas_<axis>.png into `folder`."""
    folder.mkdir(parents=True, exist_ok=True)
    js = atlas_file(folder, out.axis)
    png = js.with_suffix(".png")
    js.write_text(out.model_dump_json())
    plot_atlas(out, png)
    return [js, png]


__all__ = ["AtlasConfig", "atlas_search", "run_atlas", "write_atlas"]

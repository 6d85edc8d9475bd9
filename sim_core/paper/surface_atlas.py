"""The gait atlas from the drift surface: at each body mass (or slope) a surface over beta
(`drift_surface`), read as which of the paper's gaits have a stable zero in the window
(`PAPER_WINDOW`) and where their branches fold. The finder's atlas (`paper.atlas`) reads the
same question from settled free runs; this one also sees the folds, at a fixed price per cell.
Where the surface leaves a zero unresolved and that could change a cell's region, settled free
walks decide it (`surface_walks`); a cell is also walked from the paper's start of every gait
a neighbouring cell holds and it lacks, since a surface that leaves nothing open can still miss
a narrow pair (three committed slope cells did: docs/REPRODUCTION.md). What the atlas shows
then agrees with every walk it made; a cell that neither rule walks is the surface's word.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from sim_core.contract.choice import changed_leaves
from sim_core.contract.finder import AXIS_LABEL, AXIS_PARAM
from sim_core.contract.surface import (
    REGION_COLOURS,
    AtlasPoint,
    DriftSurface,
    SurfaceAtlas,
    SurfaceAtlasConfig,
    SurfaceConfig,
    WalkConfig,
    region,
)
from sim_core.contract.template import RunTemplate
from sim_core.model.gait import classify_gait
from sim_core.model.params import ModelParams
from sim_core.paper.analysis import PAPER_WINDOW
from sim_core.paper.surface import drift_surfaces
from sim_core.paper.surface_walks import walk_cells, window_zeros
from sim_core.runs.backends import Backend, Executor, InlineBackend, RunStats
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import execute_chunk

__all__ = ["atlas_points", "draw_atlas", "region", "surface_atlas"]


def atlas_points(surface: DriftSurface, value: float) -> list[AtlasPoint]:
    out = []
    for b in surface.betas:
        zs = window_zeros(surface, b)
        stable = [z.d31 for z in zs if z.stable]
        gaits = [classify_gait(x, b) for x in stable]
        unresolved = sum(not z.resolved for z in zs)
        unresolved += sum(1 for n in surface.near_zeros if abs(n.beta - b) < 1e-9)
        out.append(
            AtlasPoint(
                beta=b,
                value=value,
                stable=stable,
                gaits=gaits,
                unresolved=unresolved,
                region=region(gaits),
            )
        )
    return out


def surface_atlas(
    axis: str,
    betas: Sequence[float],
    values: Sequence[float],
    *,
    cache: ResultCache | None = None,
    backend: Backend | None = None,
    config: SurfaceConfig | None = None,
    params: ModelParams | None = None,
    template: RunTemplate | None = None,
    refine: bool = True,
    walks: WalkConfig | None = None,
    neighbour_walks: bool = True,
    progress: bool | str = True,
    stats: RunStats | None = None,
    on_value: Callable[[float, DriftSurface], None] | None = None,
    on_progress: Callable[[float], None] | None = None,
    executor: Executor = execute_chunk,
) -> SurfaceAtlas:
    """A drift surface over `betas` at each of `values` of `axis` ("mass": body_mass_g, g;
    "slope": slope_deg, deg), on `template` (`drift_surface`'s: every field of the runs but the
    per-run ones; RunSpec's defaults if None, so 3 g, level) with the axis's field at each
    value, read as regions and folds. All values' probes go to the backend
    together, pass by pass (`drift_surfaces`), through the cache, so an interrupted atlas
    resumes; `on_value` hears each value's surface once all are done. With `walks`, every
    cell where an unresolved zero could change the region is decided by settled free walks
    (`surface_walks.walk_cells`: all cells' walks in one batch, through the same cache); with
    `neighbour_walks` too, each cell is then walked from the paper's start of every gait a
    neighbouring cell holds and it lacks (`surface_walks.neighbour_rounds`)."""
    if axis not in AXIS_PARAM:
        raise ValueError(f"unknown atlas axis {axis!r}; choose from {sorted(AXIS_PARAM)}")
    if cache is None:
        with tempfile.TemporaryDirectory(prefix="atlas-") as tmp:
            return surface_atlas(
                axis, betas, values, cache=ResultCache(tmp), backend=backend, config=config,
                params=params, template=template, refine=refine, walks=walks,
                neighbour_walks=neighbour_walks, progress=progress, stats=stats,
                on_value=on_value, on_progress=on_progress, executor=executor,
            )  # fmt: skip
    cfg = config or SurfaceConfig()
    p = params or ModelParams()
    param = AXIS_PARAM[axis]
    base = template or RunTemplate()
    rows = [base.replace(**{param: v}) for v in values]
    # the walks' share of the progress: about what they cost in a measured row (docs)
    split = 1.0 if walks is None else 0.7

    def share(a: float, b: float) -> Callable[[float], None] | None:
        return None if on_progress is None else (lambda x: on_progress(a + (b - a) * x))

    # the bar's label on a terminal: "atlas" for the surfaces, "atlas walks" for the walks
    label = progress if isinstance(progress, str) else "atlas"
    surfaces = drift_surfaces(
        betas, rows, cache=cache, backend=backend, config=config, params=p, refine=refine,
        progress=label if progress else False, stats=stats, on_progress=share(0.0, split),
        executor=executor,
    )  # fmt: skip
    points: list[AtlasPoint] = []
    folds = []
    cells = []
    for v, row, s in zip(values, rows, surfaces, strict=True):
        points += atlas_points(s, v)
        cells += [(pt, s, row) for pt in points[-len(s.betas) :]]
        folds += [(v, f) for f in s.folds if PAPER_WINDOW[0] <= f.d31 <= PAPER_WINDOW[1]]
        if on_value is not None:
            on_value(v, s)
    walk_s = 0.0
    if walks is not None:
        points = walk_cells(
            cells, cache=cache, backend=backend or InlineBackend(), params=p, config=walks,
            chunk_size=cfg.chunk_size, progress=f"{label} walks" if progress else False,
            stats=stats, executor=executor,
            on_progress=share(split, 0.95 if neighbour_walks else 1.0),
            n_betas=len(betas) if neighbour_walks else None,
        )  # fmt: skip
        walk_s = sum(w.sim_s for pt in points for w in pt.walks)
    return SurfaceAtlas(
        axis=axis,
        param=param,
        ground=p.contact.ground,
        betas=list(betas),
        values=list(values),
        points=points,
        folds=folds,
        sim_s=sum(s.sim_s for s in surfaces) + walk_s,
        config=SurfaceAtlasConfig.of(
            cfg, refine=refine, walks=walks, neighbour_walks=walks is not None and neighbour_walks
        ),
        params=changed_leaves(p),
    )


def draw_atlas(atlas: SurfaceAtlas, path: Path) -> None:
    """Regions as coloured cells (hatched and marked "?" where the region may hide a gait:
    `AtlasPoint.undecided`), the folds of the tripod and metachronal branches as markers at
    their (beta, value)."""
    fig, ax = plt.subplots(figsize=(8.0, 4.8))
    nb, nv = len(atlas.betas), len(atlas.values)
    db = (atlas.betas[1] - atlas.betas[0]) if nb > 1 else 0.01
    for k, pt in enumerate(atlas.points):
        i = k // nb
        y0 = i - 0.5
        ax.add_patch(
            plt.Rectangle(
                (pt.beta - db / 2, y0),
                db,
                1.0,
                color=REGION_COLOURS.get(pt.region, "0.8"),
                alpha=0.55 if pt.undecided else 0.85,
                hatch="//" if pt.undecided else None,
                lw=0,
            )
        )
        if pt.undecided:
            ax.text(pt.beta, i, "?", ha="center", va="center", fontsize=8)
    for v, f in atlas.folds:
        gait = classify_gait(f.d31, f.beta_lo)
        if gait not in ("tripod", "metachronal"):
            continue
        i = atlas.values.index(v)
        marker = "<" if "rises" in f.side else ">"
        ax.plot(
            0.5 * (f.beta_lo + f.beta_hi),
            i,
            marker,
            ms=7,
            mec="k",
            color=REGION_COLOURS["tripod only" if gait == "tripod" else "metachronal only"],
        )
    for name, colour in REGION_COLOURS.items():
        ax.plot([], [], "s", color=colour, mec="0.5", label=name)
    ax.plot([], [], "<", color="0.5", mec="k", label="a branch ends as β rises")
    ax.plot([], [], ">", color="0.5", mec="k", label="a branch ends as β falls")
    ax.plot([], [], ls="none", marker="$?$", color="k", ms=6, label="unresolved")
    ax.set_xlim(atlas.betas[0] - db / 2, atlas.betas[-1] + db / 2)
    ax.set_ylim(-0.5, nv - 0.5)
    ax.set_yticks(range(nv), [f"{v:g}" for v in atlas.values])
    ax.set_xlabel("duty factor β")
    ax.set_ylabel(AXIS_LABEL.get(atlas.axis, atlas.axis))
    ax.set_title(
        f"gait atlas from the drift surface ({atlas.ground} ground)\nstable gaits with Δ31 in "
        f"{PAPER_WINDOW[0]}-{PAPER_WINDOW[1]} rad, walked where the surface cannot tell; "
        "?: unresolved",
        fontsize=9,
    )
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)

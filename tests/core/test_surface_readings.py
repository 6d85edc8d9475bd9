"""What is read off a drift surface: the reproduction rows (`surface_figures.table_rows`) and
the atlas's regions (`surface_atlas`), on synthetic surfaces whose answer is known."""

from __future__ import annotations

from pathlib import Path

import pytest

from sim_core.paper.surface import assemble
from sim_core.paper.surface_atlas import atlas_points, draw_atlas, region, surface_atlas
from sim_core.paper.surface_figures import table_rows
from sim_core.paper.surface_types import SurfaceConfig, SurfacePoint
from sim_core.paper.values import PAPER
from sim_core.runs.cache import ResultCache
from tests.core.test_surface import _pt


def _curve(beta: float, zeros: list[tuple[float, bool]]) -> list[SurfacePoint]:
    """Probes 0.02 either side of each zero with the sign its stability needs."""
    pts = []
    for x, stable in zeros:
        s = 1.0 if stable else -1.0
        pts += [_pt(beta, x - 0.02, 2.0 * s), _pt(beta, x + 0.02, -2.0 * s)]
    return pts


def test_a_bistable_map_needs_a_tripod_and_a_metachronal_state() -> None:
    cfg = SurfaceConfig()
    # at 0.655 the paper has S U S: tripod, saddle, metachronal
    paper_like = assemble(
        [0.655], _curve(0.655, [(1.9, True), (2.5, False), (2.95, True)]), cfg, sim_s=0.0
    )
    ours_like = assemble(
        [0.655], _curve(0.655, [(1.74, True), (1.81, False), (1.97, True)]), cfg, sim_s=0.0
    )

    def verdict(s: object) -> str:
        rows = table_rows(s, PAPER, 0.01)  # type: ignore[arg-type]
        return next(r[3] for r in rows if "β = 0.655" in r[0])

    assert verdict(paper_like) == "yes"
    assert verdict(ours_like) == "**no**"  # the right pattern, the wrong gaits


def test_regions_name_the_paper_gaits() -> None:
    assert region(["tripod", "metachronal"]) == "both"
    assert region(["metachronal", "metachronal"]) == "metachronal only"
    assert region(["tripod"]) == "tripod only"
    assert region(["other"]) == "other states" and region([]) == "none"
    cfg = SurfaceConfig()
    s = assemble([0.62], _curve(0.62, [(1.77, True), (2.9, False), (2.95, True)]), cfg, sim_s=0.0)
    (pt,) = atlas_points(s, 3.0)
    assert pt.region == "both" and pt.gaits == ["metachronal", "tripod"] and pt.unresolved == 0


def test_the_surface_atlas_runs_a_surface_per_value(tmp_path: Path) -> None:
    cfg = SurfaceConfig(d31_grid=(1.9, 2.3), settle_s=0.5, average_s=0.5, block_s=0.25)
    seen: list[float] = []
    atlas = surface_atlas(
        "mass",
        [0.655],
        [2.0, 4.0],
        cache=ResultCache(tmp_path),
        config=cfg,
        refine=False,
        progress=False,
        on_value=lambda v, s: seen.append(v),
    )
    assert seen == [2.0, 4.0] and [p.value for p in atlas.points] == [2.0, 4.0]
    assert atlas.param == "body_mass_g" and atlas.sim_s == pytest.approx(
        4.0
    )  # 2 values x 2 probes x 1 s
    draw_atlas(atlas, tmp_path / "atlas.png")
    assert (tmp_path / "atlas.png").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(ValueError, match="unknown atlas axis"):
        surface_atlas("speed", [0.655], [1.0], cache=ResultCache(tmp_path))

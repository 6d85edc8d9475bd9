"""What is read off a drift surface: the reproduction rows (`surface_figures.table_rows`) and
the atlas's regions (`surface_atlas`), on synthetic surfaces whose answer is known."""

from __future__ import annotations

from pathlib import Path

import pytest

from sim_core.contract.surface import AtlasPoint, SurfaceConfig, SurfacePoint, grid
from sim_core.contract.values import PAPER
from sim_core.paper.surface import assemble, bisection_probes, refinement_probes
from sim_core.paper.surface_atlas import atlas_points, draw_atlas, region, surface_atlas
from sim_core.paper.surface_check import robust_table
from sim_core.paper.surface_figures import fig7_rows, fig8_rows, table_rows
from sim_core.paper.surface_repro import free_runs_on_zeros, ghosts, off_grid_betas
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


def test_bisection_halves_wide_brackets_and_dips_and_leaves_narrow_ones() -> None:
    cfg = SurfaceConfig(d31_grid=grid(1.5, 2.5, 0.1))
    # a stable zero between 1.80 and 1.90 (0.1 wide), one already bracketed by 2.20-2.25,
    # and a dip of |d| at 2.0 where a narrow pair of zeros may hide
    curve = [(1.7, 3.0), (1.8, 2.0), (1.9, -2.0), (2.0, -0.5), (2.1, -0.8), (2.2, -1.0)]
    curve += [(2.25, 1.0), (2.3, 2.0)]
    s = assemble([0.64], [_pt(0.64, x, d) for x, d in curve], cfg, sim_s=0.0)
    assert [(z.lo, z.hi, z.resolved) for z in s.zeros] == [(1.8, 1.9, False), (2.2, 2.25, True)]
    probes = bisection_probes(s, cfg)
    assert [p.d for p in probes] == [1.85, 1.95, 2.05]  # the bracket's middle, the dip's sides
    assert {(p.beta, p.average_s) for p in probes} == {(0.64, cfg.average_s)}
    # the dip hid a pair of zeros (1.95 and 2.05 are positive); every gap is now narrow
    extra = [_pt(0.64, 1.85, 0.5), _pt(0.64, 1.95, 0.4), _pt(0.64, 2.05, 0.4)]
    halved = assemble([0.64], [*s.points, *extra], cfg, sim_s=0.0)
    found = [(round(z.d31, 3), z.stable) for z in halved.zeros]
    assert found[:3] == [(1.86, True), (1.942, False), (1.972, True)]
    assert bisection_probes(halved, cfg) == []


def test_the_last_pass_probes_unresolved_zeros_only_at_the_betas_it_is_given() -> None:
    # at both betas a stable zero between 1.80 and 1.90 that no probe pair resolves
    cfg = SurfaceConfig(d31_grid=grid(1.5, 2.5, 0.1), refine_step=0.02)
    curve = [(1.7, 3.0), (1.8, 2.0), (1.9, -2.0), (2.0, -3.0)]
    pts = [_pt(b, x, d) for b in (0.64, 0.66) for x, d in curve]
    s = assemble([0.64, 0.66], pts, cfg, sim_s=0.0)
    assert [(z.beta, z.resolved) for z in s.zeros] == [(0.64, False), (0.66, False)]
    every = refinement_probes(s, cfg)
    assert {p.beta for p in every} == {0.64, 0.66}
    assert {p.average_s for p in every} == {cfg.refine_average_s}
    only = refinement_probes(s, cfg, only=(0.66,))
    assert only == [p for p in every if p.beta == 0.66] and only


def test_a_ghost_is_a_dip_of_the_drift_that_keeps_its_sign() -> None:
    # one sign throughout 1.6-2.6, |d| dipping from 5 to 0.8 mrad at 2.0; a zero at 2.65
    xs = [1.6, 1.7, 1.8, 1.9, 2.0, 2.1, 2.2, 2.3, 2.4, 2.5, 2.6, 2.7, 2.8]
    ds = [5.0, 4.5, 3.0, 1.5, 0.8, 1.6, 3.5, 4.0, 3.0, 2.0, 1.0, -1.0, -2.0]
    s = assemble([0.64], [_pt(0.64, x, d) for x, d in zip(xs, ds, strict=True)], SurfaceConfig(),
                 sim_s=0.0)  # fmt: skip
    # the fall towards the zero at 2.65 is no ghost: |d| does not rise again before it
    assert ghosts(s, 0.64, 3e-4) == [(2.0, 8e-4)]
    # a settled free run at the stable zero agrees, one at 2.3 (no zero there) does not
    assert free_runs_on_zeros(s, 0.64, [2.66, 2.3]) == [2.3]


def test_the_robustness_table_says_how_far_each_stable_zero_moved_or_that_it_is_gone() -> None:
    cfg = SurfaceConfig()
    default = assemble([0.62], _curve(0.62, [(1.76, True), (2.95, True)]), cfg, sim_s=0.0)
    moved = assemble([0.62], _curve(0.62, [(1.78, True)]), cfg, sim_s=0.0)
    table = robust_table({"default": default, "kp_lift x1.1": moved})
    rows = {line.split(" | ")[0].strip("| "): line for line in table.splitlines()[2:]}
    assert rows["default"].endswith("| 0.000 rad |") and "1.76, 2.95" in rows["default"]
    assert rows["kp_lift x1.1"].endswith("| 0.020 rad; 1 gone |")


def _decided(beta: float, stable: list[float], sources: list[str]) -> AtlasPoint:
    from sim_core.model.gait import classify_gait

    gaits = [classify_gait(x, beta) for x in stable]
    return AtlasPoint(beta=beta, value=3.0, stable=stable, gaits=gaits, unresolved=0,
                      region=region(gaits), provenance=sources, checked=True)  # fmt: skip


def test_walks_decide_the_fig8_ranges_and_break_a_fig7_match() -> None:
    """Issue 52, point 1: where a settled walk finds a state the surface missed (the tripod at
    0.63-0.64 inside a near-zero band), the ranges and Fig. 7's pattern are the walks'."""
    cfg = SurfaceConfig()
    betas = [0.62, 0.63, 0.64, 0.65]
    pts = _curve(0.62, [(1.77, True), (2.9, False), (2.95, True)])
    for b in betas[1:]:
        pts += _curve(b, [(2.0, True)])
    s = assemble(betas, pts, cfg, sim_s=0.0)
    cells = [_decided(0.62, [1.77, 2.95], ["surface", "surface"])]
    cells += [_decided(b, [2.0, 2.95], ["surface", "walk"]) for b in (0.63, 0.64)]
    cells += [_decided(0.65, [2.0], ["surface"])]
    alone = {r[0]: r for r in fig8_rows(s, PAPER, 0.01)}
    walked = {r[0]: r for r in fig8_rows(s, PAPER, 0.01, cells)}
    key = "Fig. 8: tripod stable for β in"
    assert alone[key][2].startswith("0.62-0.62")
    assert walked[key][2].startswith("0.62-0.64 with settled walks (the surface alone: 0.62-0.62)")
    # at 0.64 the paper's lone tripod: the surface's lone metachronal state is "no" either way,
    # and the walk's tripod is named
    row = next(r for r in fig7_rows(s, PAPER, cells) if "β = 0.64" in r[0])
    assert "settled walks add 2.95 (tripod)" in row[2] and row[3] == "**no**"
    # the walks off the grid: half a step inside each end, a step and a half outside
    assert off_grid_betas(cells, "tripod") == [(0.635, True, 2.95)]
    assert off_grid_betas([*cells, _decided(0.66, [2.0], ["surface"])], "tripod") == [
        (0.635, True, 2.95), (0.655, False, 2.95)
    ]  # fmt: skip


def test_the_off_grid_row_says_which_walks_disagree() -> None:
    from sim_core.paper.reproduce import _off_grid_rows

    inside = {"gait": "tripod", "beta": 0.6425, "expected": True, "holds": True, "final": 2.95,
              "start": 2.95}  # fmt: skip
    outside = inside | {"beta": 0.6575, "expected": False, "holds": None, "final": None}
    ((_, _, ours, verdict),) = _off_grid_rows([inside, outside])
    assert verdict == "**no**" and ours.startswith("1 of 2 agree")
    assert "tripod at 0.6575 (outside): undecided" in ours
    assert _off_grid_rows([inside])[0][3] == "yes" and _off_grid_rows(None) == []


def test_a_walk_off_the_grid_that_has_left_its_gait_leaves() -> None:
    """An unsettled walk whose last quarter already lies off the gait it started on has
    left it (the tripod sliding through its ghost at 0.6525); one still on it is undecided."""
    from sim_core.contract.surface import AtlasWalk
    from sim_core.paper.surface_repro import OffGrid

    def off(final: float | None, settled: bool) -> OffGrid:
        w = AtlasWalk(start=2.95, final=final, settled=settled, why="", sim_s=40.0)
        return OffGrid("tripod", 0.6525, False, w)

    assert off(2.48, False).holds is False and off(2.48, False).agrees
    assert off(2.95, False).holds is None and not off(2.95, False).agrees
    assert off(2.95, True).holds is True and off(None, False).holds is None

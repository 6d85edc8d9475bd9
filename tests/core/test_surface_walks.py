"""Deciding atlas cells by settled free walks (`surface_walks`): which spans are walked, from
where, and what the walks make of a cell, on synthetic surfaces and the toy map
(`synthetic_gait`), whose answers are known."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from sim_core.contract.surface import AtlasPoint, AtlasWalk, SurfaceConfig
from sim_core.model.gait import classify_gait
from sim_core.paper.surface import assemble
from sim_core.paper.surface_atlas import surface_atlas
from sim_core.paper.surface_walks import (
    WalkConfig,
    certain_gaits,
    could_hold,
    decide,
    marked_if_left,
    neighbour_starts,
    open_spans,
    read_walk,
    spans_at,
    walk_starts,
)
from sim_core.runs.cache import ResultCache
from tests.core.synthetic_gait import fake_execute
from tests.core.test_surface import _pt


def _walk(start: float, final: float | None, settled: bool = True) -> AtlasWalk:
    why = "" if settled else "still drifting"
    return AtlasWalk(start=start, final=final, settled=settled, why=why, sim_s=20.0)


def _cell(stable: list[float], unresolved: int = 1) -> AtlasPoint:
    gaits = [classify_gait(x, 0.62) for x in stable]
    return AtlasPoint(beta=0.62, value=3.0, stable=stable, gaits=gaits, unresolved=unresolved,
                      region="metachronal only")  # fmt: skip


def test_only_spans_that_could_change_the_region_are_walked() -> None:
    # beta 0.62: the metachronal at 1.77 resolved, a band inside the noise floor (0.3 mrad)
    # at 2.05-2.20 (metachronal side) and the tripod's narrow pair hidden in one at 2.85-3.05
    curve = [(1.70, 3.0), (1.75, 1.0), (1.78, -2.0), (2.05, -1.0), (2.08, -0.2), (2.10, -0.1)]
    curve += [(2.17, -0.2), (2.20, -1.0), (2.85, -2.0), (2.88, -0.2), (2.93, -0.1)]
    curve += [(2.98, -0.2), (3.05, -2.0)]
    s = assemble([0.62], [_pt(0.62, x, d) for x, d in curve], SurfaceConfig(), sim_s=0.0)
    assert spans_at(s, 0.62) == [(2.05, 2.2), (2.85, 3.05)]
    assert certain_gaits(s, 0.62) == ["metachronal"]
    assert could_hold((2.85, 3.05), 0.62) == {"tripod"}
    assert could_hold((2.7, 2.8), 0.62) == {"metachronal", "tripod"}
    # the metachronal band cannot change "metachronal only"; the tripod band can
    assert open_spans(0.62, ["metachronal"], spans_at(s, 0.62)) == [(2.85, 3.05)]
    assert open_spans(0.62, ["metachronal", "tripod"], spans_at(s, 0.62)) == []
    # a cell with no stable state: any gait a band could hold changes "none"
    assert open_spans(0.62, [], [(2.05, 2.2)]) == [(2.05, 2.2)]


def test_an_unresolved_zero_across_a_gait_border_names_no_gait_for_sure() -> None:
    # + at 2.6, - at 3.3: a stable zero somewhere in between, metachronal or tripod
    s = assemble([0.62], [_pt(0.62, 2.6, 2.0), _pt(0.62, 3.3, -2.0)], SurfaceConfig(), sim_s=0.0)
    (z,) = s.zeros
    assert z.stable and not z.resolved
    assert certain_gaits(s, 0.62) == []
    assert open_spans(0.62, [], spans_at(s, 0.62)) == [(2.6, 3.3)]


def test_walks_start_on_both_sides_of_each_span_and_near_the_paper_branches() -> None:
    cfg = WalkConfig()
    assert walk_starts([], cfg) == []  # nothing to decide: no walk
    # 2.98 + 0.03 lies within merge_rad of the tripod start 3.0: one walk
    assert walk_starts([(2.88, 2.98)], cfg) == [1.9, 2.85, 3.0]
    assert walk_starts([(1.6, 1.7), (2.88, 2.98)], cfg) == [1.57, 1.73, 1.9, 2.85, 3.0]


def test_a_settled_walk_adds_its_state_and_an_unsettled_one_leaves_the_cell_unresolved() -> None:
    cell = _cell([2.273])
    walks = [_walk(1.9, 2.27), _walk(2.85, 2.275), _walk(3.0, 2.953)]
    got = decide(cell, walks, [None])
    assert got.stable == [2.273, 2.953] and got.provenance == ["surface+walk", "walk"]
    assert got.gaits == ["metachronal", "tripod"] and got.region == "both"
    assert got.checked and not got.undecided
    # the tripod walk did not settle: the region stays what the rest says, marked unresolved
    open_ = decide(cell, [_walk(2.85, 2.275), _walk(3.0, 2.99, settled=False)], [None])
    assert open_.region == "metachronal only" and open_.undecided
    # a walk that settles outside the window adds nothing there
    assert decide(cell, [_walk(3.0, 4.5)], [None]).stable == [2.273]


def test_a_walk_places_a_stable_zero_the_surface_could_only_bracket() -> None:
    # the surface: a stable zero between 2.6 and 3.3 guessed at 2.65 (metachronal)
    cell = _cell([2.65])
    got = decide(cell, [_walk(2.57, 2.93), _walk(3.33, 2.93)], [(2.6, 3.3)])
    assert got.stable == [2.93] and got.gaits == ["tripod"] and got.region == "tripod only"
    assert got.provenance == ["surface+walk"]
    # two states in one bracket: the second is the walks' own
    two = decide(cell, [_walk(2.57, 2.7), _walk(3.33, 2.93)], [(2.6, 3.3)])
    assert two.stable == [2.7, 2.93] and two.provenance == ["surface+walk", "walk"]


def test_an_atlas_written_before_the_walks_reads_its_unresolved_zeros_as_undecided() -> None:
    old = AtlasPoint.model_validate(
        {"beta": 0.62, "value": 3.0, "stable": [2.27], "gaits": ["metachronal"],
         "unresolved": 4, "region": "metachronal only"}
    )  # fmt: skip
    assert old.undecided and not old.checked and old.walks == [] and old.provenance == []
    assert not _cell([2.27], unresolved=0).undecided


def test_a_walk_is_read_by_the_settled_rule() -> None:
    still = {"d31": [2.95] * 200, "duration_s": 20.0, "error": None}
    w = read_walk(3.0, still, 40.0)
    assert w.settled and w.final is not None and abs(w.final - 2.95) < 1e-9 and w.sim_s == 20.0
    moving = {"d31": list(np.linspace(2.9, 2.5, 200)), "duration_s": None, "error": None}
    w = read_walk(3.0, moving, 40.0)
    assert not w.settled and "drifting" in w.why and w.sim_s == 40.0
    failed = read_walk(3.0, {"d31": [], "error": "diverged at 3 s"}, 40.0)
    assert not failed.settled and failed.final is None and "diverged" in failed.why


def test_the_toy_atlas_walks_where_its_coarse_surface_hides_the_tripod(tmp_path: Path) -> None:
    # the toy's map (stable 1.9 and 2.9, unstable 2.4 at beta 0.6575) probed only at 1.5, 2.6,
    # 3.3: one stable zero bracketed 2.6-3.3, placed on the metachronal side by interpolation
    cfg = SurfaceConfig(d31_grid=(1.5, 2.6, 3.3))
    cache = ResultCache(tmp_path)
    kw = {"cache": cache, "config": cfg, "refine": False, "progress": False}
    plain = surface_atlas("mass", [0.6575], [3.0], executor=fake_execute, **kw)  # type: ignore[arg-type]
    (p0,) = plain.points
    assert p0.gaits == ["metachronal"] and p0.undecided and not p0.checked
    walked = surface_atlas("mass", [0.6575], [3.0], executor=fake_execute, walks=WalkConfig(),
                           **kw)  # type: ignore[arg-type]  # fmt: skip
    (p,) = walked.points
    assert p.checked and not p.undecided and p.region == "both"
    assert [round(x, 3) for x in p.stable] == [1.9, 2.9]
    assert p.provenance == ["walk", "surface+walk"]
    assert sorted(w.start for w in p.walks) == [1.9, 2.57, 3.0, 3.33]
    assert walked.sim_s == plain.sim_s + sum(w.sim_s for w in p.walks)
    assert walked.config.walks == WalkConfig() and plain.config.walks is None
    assert "walks" not in plain.model_dump()["config"]  # an atlas not walked says nothing


def test_a_cell_is_walked_from_the_paper_start_of_a_gait_its_neighbour_holds() -> None:
    # a 2 x 2 grid (value-major): only (value 3, beta 0.66) holds the tripod
    cfg = WalkConfig()
    meta = _cell([1.8], unresolved=0)

    def at(beta: float, value: float, stable: list[float]) -> AtlasPoint:
        gaits = [classify_gait(x, beta) for x in stable]
        return meta.model_copy(update={"beta": beta, "value": value, "stable": stable,
                                       "gaits": gaits})  # fmt: skip

    grid = [at(0.64, 2.0, [1.8]), at(0.66, 2.0, [1.8]), at(0.64, 3.0, [1.8]),
            at(0.66, 3.0, [1.8, 2.95])]  # fmt: skip
    tripod_start = next(x for x in cfg.paper_starts if classify_gait(x, 0.64) == "tripod")
    assert neighbour_starts(grid, 2, cfg) == [[], [tripod_start], [tripod_start], []]
    # a cell that has walked from there already is not walked again
    walked = grid[1].model_copy(update={"walks": [_walk(tripod_start, 1.8)]})
    assert neighbour_starts([grid[0], walked, *grid[2:]], 2, cfg)[1] == []


def test_the_toy_atlas_walks_beside_a_neighbour_and_keeps_what_the_walk_finds(
    tmp_path: Path,
) -> None:
    # the toy at beta 0.63 holds the tripod only (its metachronal pair folded at 0.645), at
    # 0.6575 both, each resolved on a fine grid: 0.63 is walked from the metachronal start
    # because its neighbour holds that gait, and the walk slides to the tripod
    cfg = SurfaceConfig(d31_grid=tuple(round(1.5 + 0.05 * k, 2) for k in range(37)))
    kw = {"cache": ResultCache(tmp_path), "config": cfg, "refine": False, "progress": False}
    lone = surface_atlas("mass", [0.63, 0.6575], [3.0], executor=fake_execute,
                         walks=WalkConfig(), neighbour_walks=False, **kw)  # type: ignore[arg-type]  # fmt: skip
    atlas = surface_atlas("mass", [0.63, 0.6575], [3.0], executor=fake_execute,
                          walks=WalkConfig(), **kw)  # type: ignore[arg-type]  # fmt: skip
    low, mid = atlas.points
    assert lone.points[0].walks == [] and lone.points[0].region == "tripod only"
    assert mid.region == "both" and mid.walks == []
    meta_start = next(
        x for x in WalkConfig().paper_starts if classify_gait(x, 0.63) == "metachronal"
    )
    assert [w.start for w in low.walks] == [meta_start] and low.walks[0].settled
    assert low.region == "tripod only" and low.checked and not low.undecided
    assert atlas.config.neighbour_walks and not lone.config.neighbour_walks
    assert atlas.sim_s == lone.sim_s + low.walks[0].sim_s
    assert atlas.model_dump()["config"]["neighbour_walks"] is True
    assert "neighbour_walks" not in lone.model_dump()["config"]  # as atlases before it


def test_an_unsettled_neighbour_walk_that_left_its_gait_for_a_held_one_decides_nothing() -> None:
    # a metachronal-only cell walked from the tripod's start: still drifting at 40 s, but
    # already in the metachronal it holds, it cannot change the region; still drifting inside
    # the tripod, or into a gait the cell lacks, it leaves the cell undecided
    cell = _cell([1.8], unresolved=0)
    assert cell.gaits == ["metachronal"]
    left = marked_if_left(_walk(3.0, 1.95, settled=False), cell)
    assert left.left_gait and not left.settled
    assert not cell.model_copy(update={"walks": [left], "checked": True}).undecided
    inside = marked_if_left(_walk(3.0, 2.97, settled=False), cell)
    assert not inside.left_gait
    assert cell.model_copy(update={"walks": [inside], "checked": True}).undecided
    # a cell with no stable state: a walk from the tripod's start drifting in the
    # metachronal's range may still settle there and change the region
    empty = _cell([], unresolved=0)
    assert not marked_if_left(_walk(3.0, 2.3, settled=False), empty).left_gait
    settled = _walk(3.0, 1.8)
    assert marked_if_left(settled, cell) is settled

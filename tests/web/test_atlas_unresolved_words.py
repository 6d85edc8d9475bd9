"""The atlas panel says "unresolved" in words, not only by shade: a "?" in each cell whose
region may hide a gait (`AtlasPoint.undecided`), a legend entry for it, and the reason in the
cell's tooltip."""

from __future__ import annotations

from sim_core.contract import SurfaceAtlas
from web.atlas_svg import atlas_svg


def _atlas() -> SurfaceAtlas:
    walk = {"start": 3.0, "final": 2.95, "settled": True, "why": "", "sim_s": 20.0}
    drifting = walk | {"settled": False, "why": "still drifting"}
    base = {"value": 3.0, "stable": [2.27], "gaits": ["metachronal"], "unresolved": 2,
            "region": "metachronal only"}  # fmt: skip
    points = [
        base | {"beta": 0.62, "checked": True, "walks": [walk]},  # decided by a walk
        base | {"beta": 0.63, "checked": True, "walks": [drifting]},  # a walk did not settle
        base | {"beta": 0.64},  # written before the walks: its unresolved zeros stay open
    ]
    return SurfaceAtlas.model_validate({
        "axis": "mass", "param": "body_mass_g", "ground": "constraint",
        "betas": [0.62, 0.63, 0.64], "values": [3.0], "points": points, "folds": [],
        "sim_s": 0.0, "config": {},
    })  # fmt: skip


def test_undecided_cells_carry_a_question_mark_and_say_why() -> None:
    svg = atlas_svg(_atlas(), "", "mass", "body mass (g)", (0.63, 3.0), (0.55, 0.80))
    assert svg.count('data-unresolved="true"') == 2
    assert svg.count('<text class="unresolved"') == 2
    assert "(unresolved: a walk did not settle)" in svg and "(unresolved zeros here)" in svg
    assert "? unresolved" in svg

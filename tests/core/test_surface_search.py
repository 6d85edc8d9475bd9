"""The fifth campaign's objective (`lab.surface_search`) on synthetic surfaces whose
folds are known: the paper's map scores its folds, ours (metachronal at every speed) does not."""

from __future__ import annotations

import pytest

from lab.surface_search import (
    OBJECTIVE_BETAS,
    OBJECTIVE_CONFIG,
    PAPER_METACHRONAL_FOLD,
    fold_of,
    read_surface,
)
from sim_core.contract.surface import SurfacePoint
from sim_core.paper.surface import assemble
from tests.core.test_surface import _pt


def _drift(x: float, gaits: str) -> float:
    """mrad per cycle: 'T' tripod only (flow up to 2.92), 'M' metachronal only (to 1.92),
    'B' both, an unstable zero near 2.4 between them."""
    if gaits == "T":
        return 3.0 if x < 2.9 else -3.0
    if gaits == "M":
        return 3.0 if x < 1.9 else -3.0
    return 3.0 if x < 1.9 or 2.4 <= x < 2.9 else -3.0


def _surface(pattern: dict[float, str]) -> list[SurfacePoint]:
    return [_pt(b, x, _drift(x, g)) for b, g in pattern.items() for x in OBJECTIVE_CONFIG.d31_grid]


def _walk(speed: float = 1.0) -> list[dict[str, float]]:
    return [{"speed_ratio": speed, "slip_fraction": 0.02, "landing_swing_share": 1.0}]


PAPER_MAP = dict(zip(OBJECTIVE_BETAS, "TTBBMM", strict=True))
OURS_MAP = dict(zip(OBJECTIVE_BETAS, "BMMMMM", strict=True))


def test_the_paper_map_scores_its_folds() -> None:
    s = read_surface(
        assemble(OBJECTIVE_BETAS, _surface(PAPER_MAP), OBJECTIVE_CONFIG, sim_s=0), _walk()
    )
    assert s.metachronal_fold == pytest.approx(0.645)  # halfway between 0.635 and 0.655
    assert s.tripod_fold == pytest.approx(0.675)  # halfway between 0.665 and 0.685
    assert s.extra_zeros == 0 and s.parts["sanity"] == 0.0
    assert s.metachronal_value == pytest.approx(1.9, abs=0.06)
    assert s.tripod_value == pytest.approx(2.9, abs=0.06)
    assert s.score < 0.02


def test_a_metachronal_gait_at_every_speed_is_scored_as_a_miss() -> None:
    ours = read_surface(
        assemble(OBJECTIVE_BETAS, _surface(OURS_MAP), OBJECTIVE_CONFIG, sim_s=0), _walk()
    )
    paper = read_surface(
        assemble(OBJECTIVE_BETAS, _surface(PAPER_MAP), OBJECTIVE_CONFIG, sim_s=0), _walk()
    )
    assert ours.metachronal_fold < 0.62 and ours.tripod_fold < 0.635
    assert ours.metachronal_fold_error > 0.02 and ours.score > paper.score + 0.05
    # walking 30% too fast is penalised beyond the 10% band
    fast = read_surface(
        assemble(OBJECTIVE_BETAS, _surface(PAPER_MAP), OBJECTIVE_CONFIG, sim_s=0), _walk(1.3)
    )
    assert fast.parts["sanity"] == pytest.approx(0.5 * 0.2)


def test_a_fold_outside_the_betas_is_extrapolated_and_clipped() -> None:
    betas = (0.62, 0.64, 0.66)
    assert fold_of(betas, [1.0, 2.0, 3.0], rising=True) == pytest.approx(0.60)
    assert fold_of(betas, [-3.0, -2.0, -1.0], rising=True) == pytest.approx(0.68)
    assert fold_of(betas, [-1.0, 1.0, 2.0], rising=True) == pytest.approx(0.63)
    assert fold_of(betas, [1.0, -1.0, -2.0], rising=False) == pytest.approx(0.63)
    assert fold_of(betas, [5.0, 5.0, 5.0], rising=True) == 0.55
    # a tripod margin positive everywhere but growing with beta: it lives beyond the betas
    # (extrapolating the wrong way would put its fold inside them: trial 116 read 0.632)
    assert fold_of(betas, [1.0, 2.0, 3.0], rising=False) == 0.80
    assert fold_of(betas, [3.0, 2.0, 1.0], rising=False) == pytest.approx(0.68)
    # absent at every beta: the fold lies beyond the far end, or at the clip
    assert fold_of(betas, [-1.0, -2.0, -3.0], rising=False) == pytest.approx(0.60)
    assert fold_of(betas, [-3.0, -2.0, -1.0], rising=False) == 0.55
    assert fold_of(betas, [-1.0, -2.0, -3.0], rising=True) == 0.80
    assert PAPER_METACHRONAL_FOLD == 0.645


def test_the_search_coordinates_give_back_the_defaults() -> None:
    from lab.surface_search import SPACE5, coordinates, geometry
    from sim_core.model.params import ModelParams

    base = ModelParams()
    c = coordinates(base)
    for name, r in SPACE5.items():  # the defaults lie inside the searched ranges
        assert r.low <= c[name] <= r.high, name
    back = ModelParams.of(**geometry(c))
    for name in ("foot_y", "stand_height", "stance_x_fore", "stance_x_hind", "swing_height"):
        assert back.leaf(name) == pytest.approx(base.leaf(name), rel=1e-12), name


def test_the_pareto_front_keeps_only_the_undominated() -> None:
    from lab.campaigns.campaign5_landscape import pareto

    pts = [(0.01, 0.05, 1), (0.02, 0.02, 2), (0.03, 0.03, 3), (0.05, 0.01, 4), (0.01, 0.06, 5)]
    assert pareto(pts) == [(0.01, 0.05, 1), (0.02, 0.02, 2), (0.05, 0.01, 4)]


def test_an_exported_trial_is_rescored_from_its_margins() -> None:
    from lab.campaigns.campaign5_search import rescore

    margins_t = [0.0033, 0.0024, 0.0018, 0.0019, 0.0021, 0.0028]  # trial 116: tripod everywhere
    margins_m = [-0.0011, -0.0019, 0.0025, 0.0025, 0.0022, 0.0024]
    parts = {"metachronal_fold": 0.0, "tripod_fold": 0.038, "extra_zeros": 0.02, "sanity": 0.0}
    row = {"value": 0.058, "user_attrs": {"metachronal_margin": margins_m,
           "tripod_margin": margins_t, **{f"part_{k}": v for k, v in parts.items()}}}  # fmt: skip
    new = rescore(row)
    assert new["user_attrs"]["tripod_fold"] == 0.80  # beyond the betas, not 0.632
    assert new["user_attrs"]["metachronal_fold"] == pytest.approx(0.6435, abs=1e-3)
    assert new["value"] == pytest.approx(0.0015 + 0.13 + 0.02, abs=1e-3)

"""The pull objective of the wide search: closeness to the paper's branches, sanity penalties."""

import pytest

from lab.objectives import PullEvaluation, evaluate_pull
from lab.space import WIDE_SPACE
from sim_core import ModelParams
from sim_core.model.params import PARAMETER_NAMES


def _pe(fast: list[float | None], slow: list[float | None], share: float = 0.95,
        slip: float = 0.01, err: float = 0.02) -> PullEvaluation:  # fmt: skip
    return PullEvaluation(
        finals={0.62: fast, 0.70: slow},
        landing_share={0.62: share, 0.70: share},
        slip={0.62: slip, 0.70: slip},
        speed_error={0.62: err, 0.70: err},
    )


def test_the_papers_fig5_scores_zero_and_moving_toward_it_counts() -> None:
    paper = _pe([2.9] * 6, [1.9] * 6)
    assert paper.score() == pytest.approx(0.0)
    nearer = _pe([2.7] * 6, [1.9] * 6)  # 0.2 rad short of the tripod branch
    further = _pe([2.4] * 6, [1.9] * 6)
    swapped = _pe([1.9] * 6, [2.9] * 6)
    assert paper.score() < nearer.score() < further.score() < swapped.score()
    # a diverged run is as bad as one ending opposite the branch
    assert _pe([None] * 6, [1.9] * 6).score() == pytest.approx(
        _pe([2.9 + 3.14159] * 6, [1.9] * 6).score(), abs=1e-6
    )


def test_insane_walking_costs_more_than_the_whole_closeness_range() -> None:
    mid_swing = _pe([2.9] * 6, [1.9] * 6, share=0.5)  # feet land as the scuff window closes
    slipping = _pe([2.9] * 6, [1.9] * 6, slip=0.6)
    slow = _pe([2.9] * 6, [1.9] * 6, err=0.7)
    defaults_like = _pe([2.05] * 6, [1.68] * 6)
    for bad in (mid_swing, slipping, slow):
        assert bad.score() > defaults_like.score()


def test_wide_space_stays_inside_the_models_own_bounds() -> None:
    for name, r in WIDE_SPACE.items():
        assert name in PARAMETER_NAMES
        assert r.low < r.high and len(r.reason) > 10
        ModelParams.of(**{name: r.low})
        ModelParams.of(**{name: r.high})


def test_a_tiny_closed_loop_evaluation() -> None:
    pe = evaluate_pull(ModelParams(), n_init=2, duration_s=0.8)
    assert set(pe.finals) == {0.62, 0.70}
    assert all(len(v) == 2 for v in pe.finals.values())
    assert 0.0 <= pe.closeness() <= 1.0 and pe.penalty() >= 0.0


def test_the_bistable_beta_counts_only_when_both_branches_are_reached() -> None:
    both = _pe([2.9] * 6, [1.9] * 6)
    both.finals[0.655] = [2.9, 1.9, 2.4, 2.4]
    one = _pe([2.9] * 6, [1.9] * 6)
    one.finals[0.655] = [2.9, 2.9, 3.0, 3.0]  # never near 1.9
    assert both.closeness() == pytest.approx(1.0)
    assert one.closeness() == pytest.approx((1 + 1 + 0.5) / 3, abs=1e-3)

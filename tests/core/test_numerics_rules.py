"""The grid's rule for "same gaits": labels, except across the classifier's boundary."""

from __future__ import annotations

from sim_core.gait import classify_gait
from sim_core.numerics import same_gaits


def _labels(xs: list[float | None]) -> list[str | None]:
    return [None if x is None else classify_gait(x) for x in xs]


def test_outcomes_straddling_the_classifier_boundary_are_one_gait() -> None:
    ref, run = [2.526, 1.70], [2.543, 1.71]
    assert _labels(ref)[0] != _labels(run)[0]  # the straddle this rule exists for
    assert same_gaits(run, _labels(run), ref, _labels(ref))


def test_a_different_attractor_is_a_different_gait() -> None:
    ref, run = [2.05, 1.70], [3.29, 1.70]
    assert not same_gaits(run, _labels(run), ref, _labels(ref))


def test_a_missing_outcome_is_never_the_same_gait() -> None:
    ref, run = [2.05], [None]
    assert not same_gaits(run, _labels(run), ref, _labels(ref))

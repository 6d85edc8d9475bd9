"""The grid's rule for "same gaits": labels, except across the classifier's boundary."""

from __future__ import annotations

from sim_core.model.gait import classify_gait
from sim_core.numerics.convergence import same_gaits


def test_outcomes_straddling_the_classifier_boundary_are_one_gait() -> None:
    ref, run = [2.526, 1.70], [2.543, 1.71]
    assert classify_gait(ref[0]) != classify_gait(run[0])  # the straddle this rule exists for
    assert same_gaits(run, ref)


def test_a_different_attractor_is_a_different_gait() -> None:
    ref, run = [2.05, 1.70], [3.29, 1.70]
    assert not same_gaits(run, ref)


def test_a_missing_outcome_is_never_the_same_gait() -> None:
    ref: list[float | None] = [2.05]
    run: list[float | None] = [None]
    assert not same_gaits(run, ref)

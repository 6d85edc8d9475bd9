"""The grid's rule for "same gaits": labels, except across the classifier's boundary."""

from __future__ import annotations

from sim_core.model.gait import classify_gait
from sim_core.numerics.convergence import same_gaits


def test_outcomes_straddling_the_classifier_boundary_are_one_gait() -> None:
    ref, run, betas = [2.77, 1.70], [2.79, 1.71], [0.655, 0.655]  # the tripod's edge: 2.78
    assert classify_gait(ref[0], 0.655) != classify_gait(run[0], 0.655)  # the straddle
    assert same_gaits(run, ref, betas)


def test_a_different_attractor_is_a_different_gait() -> None:
    ref, run = [2.05, 1.70], [3.29, 1.70]
    assert not same_gaits(run, ref, [0.655, 0.655])


def test_a_missing_outcome_is_never_the_same_gait() -> None:
    ref: list[float | None] = [2.05]
    run: list[float | None] = [None]
    assert not same_gaits(run, ref, [0.655])

"""The sixth campaign's walk objective (`lab.walk_objective`): how a walk is read as holding its
branch, how the folds follow from the holds along beta, and that the paper's own answer scores
zero on the folds."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from lab.walk_objective import (
    FOLD_STEP,
    HOLD_DRIFT,
    OTHER,
    STARTS,
    WALK_BETAS,
    Walk,
    fold_from_holds,
    lives,
    read_walk,
    score_walks,
)


def _series(final: float, drift: float, n: int = 160) -> list[float]:
    return list(final + drift * (np.arange(n) - (n - 1)))


def test_a_walk_holds_in_its_window_when_its_drift_is_small() -> None:
    still = read_walk("metachronal", 0.66, {"d31": _series(1.9, 0.0)}, 3.0)
    assert still.holds and still.final == pytest.approx(1.9)
    ghost = read_walk("metachronal", 0.66, {"d31": _series(1.9, 3 * HOLD_DRIFT)}, 3.0)
    assert not ghost.holds  # in the window, but sliding through it
    away = read_walk("tripod", 0.66, {"d31": _series(1.9, 0.0)}, 3.0)
    assert not away.holds  # settled, on the other branch
    upper = read_walk("tripod", 0.66, {"d31": _series(3.37, 0.0)}, 3.0)
    assert not upper.holds  # the soft legs' pi + 0.2 is not the paper's tripod
    failed = read_walk("tripod", 0.66, {"d31": [], "failure": {"kind": "fell"}}, 3.0)
    assert failed.failed and not failed.holds


@pytest.mark.parametrize(
    ("holds", "rising", "fold", "miss"),
    [
        ([False, False, True, True, True], True, 0.645, 0),  # the paper's metachronal side
        ([True, True, True, False, False], False, 0.67, 0),  # the paper's tripod
        ([True] * 5, True, 0.62 - FOLD_STEP, 0),  # present everywhere: below the grid
        ([False] * 5, True, 0.70 + FOLD_STEP, 0),  # absent everywhere: above it
        ([False, False, True, False, True], True, 0.645, 1),  # one walk against the best split
    ],
)
def test_the_fold_is_the_best_monotone_split(
    holds: list[bool], rising: bool, fold: float, miss: int
) -> None:
    f, m = fold_from_holds(WALK_BETAS, holds, rising)
    assert f == pytest.approx(fold) and m == miss


def _walk(side: str, beta: float, holds: bool, final: float) -> Walk:
    return Walk(side, beta, final, 0.0, holds, False, 1.0, 0.01, 0.98)


TARGET = {"metachronal": 1.9, "tripod": 2.9}


def _paper_walk(side: str, beta: float, present: bool) -> Walk:
    """A walk that holds its branch where `present`, else ends on the other gait."""
    return _walk(side, beta, present, TARGET[side] if present else TARGET[OTHER[side]])


def test_the_papers_answer_scores_only_its_branch_values() -> None:
    walks = [_paper_walk(s, b, lives(s, b)) for b in WALK_BETAS for s in STARTS]
    sc = score_walks(walks)
    assert sc.against_paper == 0
    assert sc.metachronal_fold == pytest.approx(0.645) and sc.tripod_fold == pytest.approx(0.67)
    assert sc.score == pytest.approx(0.0)
    # the stiff defaults' pattern: the metachronal gait everywhere, the tripod to ~0.645
    stiff = [_paper_walk(s, b, s == "metachronal" or b < 0.645) for b in WALK_BETAS
             for s in STARTS]  # fmt: skip
    worse = score_walks(stiff)
    assert worse.against_paper == 3 and worse.score > 0.05


def test_leaving_for_a_third_state_is_not_the_papers_switch() -> None:
    """An upper state that slides out of the tripod's window as beta grows (the soft legs with
    a short lift time constant: 3.12 at 0.62 to 3.27 at 0.70) reads as a tripod that "leaves"
    above 0.67; the paper's tripod ends by jumping to the metachronal gait, so the walk counts
    against the paper and costs a mismatch, although the folds read right."""
    paper = [_paper_walk(s, b, lives(s, b)) for b in WALK_BETAS for s in STARTS]
    slid = [w if w.side == "metachronal" or lives(w.side, w.beta)
            else _walk("tripod", w.beta, False, 3.27) for w in paper]  # fmt: skip
    right, wrong = score_walks(paper), score_walks(slid)
    assert wrong.tripod_fold == pytest.approx(right.tripod_fold)
    assert wrong.against_paper == 2 and right.against_paper == 0
    assert wrong.parts["third_states"] == pytest.approx(0.02) and wrong.score > right.score
    # a tripod still sliding away at 16 s (the defaults' ghost at 0.685: 2.81 at -3.8
    # mrad/cycle) is on its way, not in a third state
    away = Walk("tripod", 0.0, 2.81, -3.8e-3, False, False, 1.0, 0.01, 0.98)
    moving = [replace(away, beta=w.beta) if w.side == "tripod" and not lives(w.side, w.beta)
              else w for w in paper]  # fmt: skip
    on_its_way = score_walks(moving)
    assert on_its_way.against_paper == 0 and on_its_way.parts["third_states"] == 0.0

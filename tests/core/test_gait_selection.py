"""Gait selection on the defaults against the paper's Fig. 5, with the issue's tolerance (0.25 rad).

Two starts per beta, 5 s each, one batch. The metachronal half is reproduced and pinned; the
tripod half is not (docs/REPRODUCTION.md) and is a strict xfail: if it starts passing, the
documentation is out of date and this test says so.
"""

import math

import numpy as np
import pytest

from sim_core.model.gait import angle_diff
from sim_core.model.runner import simulate_batch
from sim_core.model.spec import RunResult, RunSpec
from sim_core.paper.values import METACHRONAL_BRANCH, TRIPOD_BRANCH

TOLERANCE = 0.25  # rad, the acceptance
STARTS = (0.8, 1.6)


@pytest.fixture(scope="module")
def finals() -> dict[float, list[RunResult]]:
    specs = [RunSpec(beta=b, d31_init=x, duration_s=5.0) for b in (0.62, 0.70) for x in STARTS]
    res = simulate_batch(specs)
    return {0.62: res[:2], 0.70: res[2:]}


def _settled(r: RunResult) -> float:
    assert not r.diverged, r.error
    tail = r.d31[-6:]
    assert np.ptp(np.unwrap(tail)) < 0.05, f"still moving: {tail}"
    return float(tail[-1])


def test_low_speed_lands_on_the_metachronal_branch(finals: dict[float, list[RunResult]]) -> None:
    for r in finals[0.70]:
        d = _settled(r)
        assert abs(float(angle_diff(d, METACHRONAL_BRANCH))) < TOLERANCE, d
        assert r.speed_cm_s is not None and abs(r.speed_cm_s - 2.5) < 0.25
        assert r.slip_fraction is not None and r.slip_fraction < 0.1


@pytest.mark.xfail(strict=True, reason="tripod branch at beta 0.62 not reproduced (REPRODUCTION)")
def test_high_speed_lands_on_the_tripod_branch(finals: dict[float, list[RunResult]]) -> None:
    for r in finals[0.62]:
        d = _settled(r)
        assert abs(float(angle_diff(d, TRIPOD_BRANCH))) < TOLERANCE, d


def test_the_branch_moves_toward_the_tripod_as_speed_rises(
    finals: dict[float, list[RunResult]],
) -> None:
    # what the model does do at high speed: the same branch, higher (measured 2.05 vs 1.68)
    fast = np.mean([_settled(r) for r in finals[0.62]])
    slow = np.mean([_settled(r) for r in finals[0.70]])
    assert fast - slow > 0.2
    assert fast < math.pi

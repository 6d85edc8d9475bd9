"""The settled fixed-point finder on the paper-like toy map (known answers, no simulator) and
the settled rule on synthetic series."""

import math

import numpy as np
import pytest

from sim_core.model.gait import TAIL_DRIFT_SETTLED, settling
from sim_core.paper.fixedpoints import (
    Cell,
    FinderConfig,
    _clusters,
    find,
    map_slope,
    parting,
    slowest_passage,
)
from tests.core.synthetic_gait import fake_runner

CFG = FinderConfig()


def test_bistable_beta_gives_two_gaits_and_the_bisected_saddle_between() -> None:
    (c,) = find([Cell(0.655)], CFG, fake_runner)
    window = sorted((a for a in c.attractors if 1.4 < a.d31 < 3.4), key=lambda a: a.d31)
    assert [a.gait for a in window] == ["metachronal", "tripod"]
    assert window[0].d31 == pytest.approx(1.9, abs=0.1) and window[1].d31 == pytest.approx(
        2.9, abs=0.1
    )
    assert all(a.slope is not None and 0 <= a.slope < 1 for a in window)
    assert sum(a.starts for a in c.attractors) == CFG.starts and not c.unsettled
    inside = [b for b in c.borders if b.d31 is not None and 1.4 < b.d31 < 3.4]
    (b,) = inside
    assert b.resolved and b.start_hi - b.start_lo <= CFG.border_tol_rad
    assert b.d31 == pytest.approx(2.4, abs=0.05)  # the toy's saddle
    assert b.slope is not None and b.slope > 1  # it repels
    assert c.pattern() == "S U S"


def test_past_a_fold_one_gait_and_its_ghost() -> None:
    (c,) = find([Cell(0.64)], CFG, fake_runner)
    assert [a.gait for a in c.attractors if 1.4 < a.d31 < 3.4] == ["tripod"]
    assert any(abs(g.d31 - 2.1) < 0.15 and abs(g.drift) < 0.02 for g in c.ghosts), c.ghosts


def test_a_run_that_does_not_settle_is_listed_not_guessed() -> None:
    def sliding(batch):  # 1 mrad per cycle forever: no attractor anywhere
        return [{"d31": list((p.d31_init + 0.001 * np.arange(400)) % (2 * math.pi)),
                 "error": None} for _, p in batch]  # fmt: skip

    (c,) = find([Cell(0.66)], FinderConfig(starts=4), sliding)
    assert not c.attractors and not c.borders
    assert len(c.unsettled) == 4 and all("still drifting" in r.why for r in c.unsettled)


def test_failed_runs_are_kept_with_their_failure() -> None:
    (c,) = find(
        [Cell(0.66)], FinderConfig(starts=2), lambda b: [{"d31": [], "error": "flipped"}] * len(b)
    )
    assert [r.failure for r in c.runs] == ["flipped", "flipped"] and not c.attractors


def test_settled_rule() -> None:
    slide = (2.9 - 0.003 * np.arange(200)) % (2 * math.pi)  # a ghost's 3 mrad per cycle
    s = settling(slide)
    assert not s.settled and "drifting" in s.why and s.drift == pytest.approx(-0.003)
    rng = np.random.default_rng(1)
    fixed = (6.27 + 0.002 * rng.standard_normal(200)) % (2 * math.pi)  # across 0 = 2 pi
    s = settling(fixed)
    assert s.settled and s.final is not None and min(s.final, 2 * math.pi - s.final) < 0.05
    assert abs(s.drift or 1) < TAIL_DRIFT_SETTLED
    short = settling(np.full(100, 2.9))  # 25 touchdowns in the last quarter: too short to judge
    assert not short.settled and "run longer" in short.why


def test_pure_helpers() -> None:
    assert [len(c.finals) for c in _clusters([6.27, 0.01, 2.9, 2.93, 1.9])] == [2, 1, 2]
    x = 2.0 + 0.5 * 0.8 ** np.arange(60)  # approach with slope 0.8 per cycle
    slope, pairs = map_slope([x], 2.0)
    assert slope == pytest.approx(0.8**4, rel=1e-6) and pairs >= 5
    a = 2.4 + 1e-3 * 1.2 ** np.arange(60)  # two runs leaving a saddle at 2.4, one each way
    b = 2.4 - 1e-3 * 1.2 ** np.arange(60)
    dwell, growth = parting(np.clip(a, 0, 6), np.clip(b, 0, 6))
    assert dwell == pytest.approx(2.4, abs=0.01) and growth == pytest.approx(1.2**4, rel=1e-6)
    ghost = np.concatenate([np.linspace(3.5, 3.0, 20), np.full(60, 3.0) - 1e-4 * np.arange(60),
                            np.linspace(2.99, 2.0, 40), np.full(100, 2.0)])  # fmt: skip
    g = slowest_passage(ghost, 2.0)
    assert g is not None and g.d31 == pytest.approx(3.0, abs=0.02) and g.cycles >= 20

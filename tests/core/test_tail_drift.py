"""`gait.tail_drift`: the drift over the last quarter tells a slow slide from an attractor."""

import math

import numpy as np

from sim_core.model.gait import SETTLED_LAST, TAIL_DRIFT_SETTLED, is_settled, tail_drift


def test_a_slide_through_a_ghost_is_not_settled_though_its_spread_is_small() -> None:
    slide = (2.9 - 0.003 * np.arange(200)) % (2 * math.pi)  # 3 mrad per cycle, as measured
    final, drift = tail_drift(slide) or (None, None)
    assert drift is not None and abs(drift + 0.003) < 1e-9
    assert final is not None and abs(final - (2.9 - 0.003 * 174.5)) < 1e-6  # the quarter's mean
    assert abs(drift) > TAIL_DRIFT_SETTLED  # the drift rule sees this slide ...
    assert is_settled(slide[-SETTLED_LAST:])  # ... where the spread rule does not


def test_an_attractor_across_the_wrap_has_no_drift() -> None:
    rng = np.random.default_rng(1)
    fixed = (6.25 + 0.01 * rng.standard_normal(80)) % (2 * math.pi)  # straddles 0 = 2 pi
    final, drift = tail_drift(fixed) or (None, None)
    assert drift is not None and abs(drift) < 1e-3
    assert final is not None and min(final, 2 * math.pi - final) < 0.1
    assert tail_drift([1.0] * 7) is None

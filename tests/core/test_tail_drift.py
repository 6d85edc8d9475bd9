"""THE settled rule (`gait.settling`, which every result reports) against the window label
(`gait.window_gait`, the gait a run walks now): only the first sees a slow slide."""

import math

import numpy as np

from sim_core.model.gait import (
    NOT_SETTLED,
    TAIL_DRIFT_SETTLED,
    WINDOW_LAST,
    final_d31,
    settling,
    window_d31,
    window_gait,
)


def test_a_slide_through_a_ghost_is_not_settled_though_its_window_is_tight() -> None:
    slide = (2.9 - 0.003 * np.arange(200)) % (2 * math.pi)  # 3 mrad per cycle, as measured
    s = settling(slide)
    assert s.drift is not None and abs(s.drift + 0.003) < 1e-9
    assert s.final is not None and abs(s.final - (2.9 - 0.003 * 174.5)) < 1e-6  # the quarter
    assert not s.settled and abs(s.drift) > TAIL_DRIFT_SETTLED  # the drift rule sees it ...
    assert window_d31(slide[-WINDOW_LAST:]) is not None  # ... where a window does not
    assert final_d31(slide) == (s.final, NOT_SETTLED)  # and results report the drift rule


def test_an_attractor_across_the_wrap_has_no_drift_and_its_gait() -> None:
    rng = np.random.default_rng(1)
    fixed = (3.0 + 0.002 * rng.standard_normal(200)) % (2 * math.pi)
    s = settling(fixed)
    assert s.settled and s.drift is not None and abs(s.drift) < 1e-4
    assert final_d31(fixed) == (s.final, "tripod") and window_gait(fixed) == "tripod"
    wrapped = (6.25 + 0.01 * rng.standard_normal(80)) % (2 * math.pi)  # straddles 0 = 2 pi
    w = settling(wrapped)
    assert w.final is not None and min(w.final, 2 * math.pi - w.final) < 0.1
    assert settling([1.0] * 7).final is None and final_d31([1.0] * 7) == (None, NOT_SETTLED)
    assert window_gait([1.0, 4.0, 2.0]) == "other"  # a window that moves names no gait

"""The gait measures defined once in `sim_core.model.gait`: THE settled rule (`settling`, which
every result reports) against the window label (`window_gait`, the gait walked now), and the
speed along the heading."""

import math

import numpy as np
import pytest

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
    assert settling([1.0] * 7).final is None and final_d31([1.0] * 7) == (1.0, NOT_SETTLED)
    assert final_d31([1.0, 1.0]) == (None, NOT_SETTLED)  # too short to say where it ends
    assert window_gait([1.0, 4.0, 2.0]) == "other"  # a window that moves names no gait


def test_speed_is_measured_along_the_heading_not_world_x() -> None:
    from sim_core.model.gait import forward_speed, heading_speed, yaw_of

    def quat(yaw: float) -> np.ndarray:
        return np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])

    assert float(yaw_of(quat(0.7))) == pytest.approx(0.7)
    t = 0.1 * np.arange(11)
    # turned 90 degrees, walking forwards (along +y) at 2 cm/s: world-x speed would read 0
    pos = np.stack([np.zeros(11), 0.02 * t, np.zeros(11)], axis=1)
    v, heading = heading_speed(t, pos, np.tile(quat(math.pi / 2), (11, 1)))
    assert v == pytest.approx(0.02) and heading == pytest.approx(math.pi / 2)
    # turned 180 degrees, wobbling across +-pi, walking forwards (towards -x): positive
    pos = np.stack([-0.02 * t, np.zeros(11), np.zeros(11)], axis=1)
    q = np.array([quat(math.pi + 0.01 * (-1) ** k) for k in range(11)])
    assert heading_speed(t, pos, q)[0] == pytest.approx(0.02, rel=1e-3)
    # sliding backwards reads negative; too short a record reads nothing
    back = np.stack([-0.01 * t, np.zeros(11), np.zeros(11)], axis=1)
    assert forward_speed(t, back, np.tile(quat(0.0), (11, 1))) == pytest.approx(-0.01)
    assert heading_speed(t[:1], pos[:1], q[:1]) == (None, None)

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
    classify_gait,
    final_d31,
    footfall_gait,
    ideal_lifts,
    measured_footfall,
    run_gait,
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
    assert final_d31(slide) == s.final and run_gait(s, None) == NOT_SETTLED  # results: the rule


def test_an_attractor_across_the_wrap_has_no_drift_and_its_gait() -> None:
    rng = np.random.default_rng(1)
    fixed = (3.0 + 0.002 * rng.standard_normal(200)) % (2 * math.pi)
    s = settling(fixed)
    assert s.settled and s.drift is not None and abs(s.drift) < 1e-4
    assert final_d31(fixed) == s.final and window_gait(fixed, 0.62) == "tripod"
    wrapped = (6.25 + 0.01 * rng.standard_normal(80)) % (2 * math.pi)  # straddles 0 = 2 pi
    w = settling(wrapped)
    assert w.final is not None and min(w.final, 2 * math.pi - w.final) < 0.1
    assert settling([1.0] * 7).final is None and final_d31([1.0] * 7) == 1.0
    assert final_d31([1.0, 1.0]) is None  # too short to say where it ends
    assert window_gait([1.0, 4.0, 2.0], 0.62) == "other"  # a window that moves names no gait


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


# the model's settled branches (30-40 s runs, 2026-11-26/27: docs/REPRODUCTION.md; issue 30,
# point 2), which the old Delta31 windows named wrongly at 0.56, >= 0.75 and downhill
BRANCHES = [
    (0.56, 2.62, "metachronal"),  # the old tripod window [2.54, 3.74] called it tripod
    (0.56, 2.94, "tripod"),
    (0.62, 2.95, "tripod"),
    (0.62, 2.12, "metachronal"),
    (0.62, 1.77, "metachronal"),
    (0.70, 1.685, "metachronal"),
    (0.75, 1.60, "metachronal"),  # old windows: "other"
    (0.80, 1.60, "metachronal"),
    (0.66, 1.56, "metachronal"),  # downhill -20 deg; old windows: "other"
    (0.66, 3.06, "tripod"),  # the tripod on a slope
]


@pytest.mark.parametrize(("beta", "d31", "gait"), BRANCHES)
def test_the_model_branches_read_as_their_footfall(beta: float, d31: float, gait: str) -> None:
    assert classify_gait(d31, beta) == gait


def test_footfall_rules_are_about_swings_not_one_band_of_delta31() -> None:
    # one Delta31, two gaits: at a low duty factor the tripods' long swings overlap enough
    assert classify_gait(2.75, 0.56) == "tripod" and classify_gait(2.75, 0.70) == "metachronal"
    # a front-to-back wave, and fore and middle legs in the air together most of a swing
    assert classify_gait(4.2, 0.62) == "other" and classify_gait(0.9, 0.62) == "other"
    assert classify_gait(float("nan"), 0.62) == "other" and classify_gait(None, 0.62) == "other"
    # the pattern, not the legs' labels: a tripod whose right side is shifted is no tripod
    lift = ideal_lifts(math.pi)
    assert footfall_gait(lift, 2.4) == "tripod"
    lift[[1, 3, 5]] += 1.5
    assert footfall_gait(lift, 2.4) != "tripod"


def test_measured_footfall_reads_the_pattern_back_from_events() -> None:
    beta, d31, period = 0.66, 1.8, 0.2
    lifts = ideal_lifts(d31)
    cycles = np.arange(40.0)
    lo = [period * (cycles + a / (2 * math.pi)) for a in lifts]
    td = [t + period * (1 - beta) for t in lo]
    ff = measured_footfall(td, lo, 1.0, 7.0)
    assert ff is not None
    got, swing = ff
    assert np.allclose(np.asarray(angle_diff_all(got, lifts)), 0.0, atol=1e-9)
    assert swing == pytest.approx(2 * math.pi * (1 - beta))
    assert footfall_gait(*ff) == classify_gait(d31, beta) == "metachronal"
    assert measured_footfall(td, lo, 1.0, 1.3) is None  # under two cycles of leg 1


def angle_diff_all(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Each leg's phase relative to leg 1, compared: a pattern has no absolute origin."""
    return np.mod((a - a[0]) - (b - b[0]) + math.pi, 2 * math.pi) - math.pi


def test_the_live_label_says_changing_while_delta31_drifts_and_reads_the_footfall_otherwise() -> (
    None
):
    from sim_core.model.gait import CHANGING, live_gait

    beta, period = 0.62, 0.1
    times = [period * k for k in range(12)]
    # a tripod footfall: legs 1, 4, 5 lift together, 2, 3, 6 half a cycle later
    lift_phase = [0.0, 0.5, 0.5, 0.0, 0.0, 0.5]
    liftoffs = [[t + p * period for t in times] for p in lift_phase]
    touchdowns = [[t + (1 - beta) * period for t in lo] for lo in liftoffs]
    still = [3.0 + 0.001 * (k % 2) for k in range(12)]
    assert live_gait(still, times, touchdowns, liftoffs, times[-1], beta) == "tripod"
    sliding = [3.0 - 0.01 * k for k in range(12)]  # 10 mrad per cycle: far beyond the rule
    assert live_gait(sliding, times, touchdowns, liftoffs, times[-1], beta) == CHANGING
    # too few cycles for a footfall: the Delta31 window decides
    assert live_gait(still[:3], times[:3], touchdowns, liftoffs, times[2], beta) == "tripod"

"""The viewer's pure parts: slider mapping, ramp, request queue, buffers, pacing, readouts."""

import math
import threading

import numpy as np
import pytest

from sim_core import RunSpec
from web import controls
from web.footfall import D31Trace, FootfallBuffer
from web.pacing import RateMeter, SimClock
from web.panels import Readouts, format_readouts
from web.requests import RequestQueue, Reset, SetBeta, SetSlope, StartRamp, coalesce
from web.svg import d31_svg, footfall_svg


def test_sliders_map_to_values_the_core_accepts() -> None:
    assert controls.beta_value(0.62) == 0.62
    assert controls.beta_value(2.0) == controls.BETA.hi
    assert controls.beta_value(float("nan")) == controls.BETA.initial
    assert controls.body_mass_g_value(-1) == controls.BODY_MASS_G.lo
    assert controls.slope_deg_value(45) == controls.SLOPE_DEG.hi
    assert controls.d31_init_value(100) <= 2 * math.pi
    for s in (controls.BETA, controls.BODY_MASS_G, controls.SLOPE_DEG):
        # every slider end is a valid RunSpec value
        RunSpec(
            beta=controls.beta_value(s.lo if s is controls.BETA else 0.66),
            body_mass_g=controls.body_mass_g_value(s.lo if s is controls.BODY_MASS_G else 3),
            slope_deg=controls.slope_deg_value(s.hi if s is controls.SLOPE_DEG else 0),
        )
    assert controls.speed_value("max") is None and controls.speed_value("0.1x") == 0.1


def test_beta_ramp_goes_down_up_and_back() -> None:
    ramp = controls.BetaRamp(start=0.66, lo=0.62, hi=0.70, rate_per_s=0.01)
    assert ramp.beta_at(0) == 0.66
    assert ramp.beta_at(4) == pytest.approx(0.62) and ramp.direction_at(3) == "down"
    assert ramp.beta_at(12) == pytest.approx(0.70) and ramp.direction_at(10) == "up"
    assert ramp.beta_at(ramp.duration_s + 1) == pytest.approx(0.66)
    assert ramp.direction_at(ramp.duration_s + 1) == "done"
    with pytest.raises(ValueError):
        controls.BetaRamp(start=0.66, rate_per_s=0)


def test_coalesce_keeps_only_the_latest_setting_but_respects_order() -> None:
    reqs = [SetBeta(0.6), SetBeta(0.61), SetSlope(2.0), SetBeta(0.62)]
    assert coalesce(reqs) == [SetBeta(0.62), SetSlope(2.0)]
    ordered = [SetBeta(0.6), StartRamp(0.01), SetBeta(0.7), Reset(2.0), SetBeta(0.65)]
    assert coalesce(ordered) == ordered


def test_request_queue_is_safe_across_threads() -> None:
    q = RequestQueue()

    def push(k: int) -> None:
        for i in range(200):
            q.put(Reset(float(k * 1000 + i)))

    threads = [threading.Thread(target=push, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    drained = q.drain()
    assert len(drained) == 800 and q.drain() == []


def test_footfall_buffer_makes_bars_and_starts_over_on_reset() -> None:
    buf = FootfallBuffer(window_s=1.0)
    for k in range(21):
        t = k * 0.1
        buf.append(t, [t % 0.4 < 0.2] + [True] * 5)
    bars = buf.bars()
    assert len(bars) == 6
    assert all(b > a for a, b in bars[0]) and len(bars[0]) >= 2
    assert bars[1] == [(pytest.approx(1.0), pytest.approx(2.0))]  # clipped to the window
    buf.append(0.05, [False] * 6)  # time went backwards: a reset
    assert len(buf) == 1
    with pytest.raises(ValueError):
        buf.append(1.0, [True] * 5)


def test_d31_trace_takes_only_new_events() -> None:
    tr = D31Trace()
    assert tr.sync([(0.1, 2.0), (0.2, 2.1)], 0.66) == 2
    assert tr.sync([(0.1, 2.0), (0.2, 2.1), (0.3, 2.2)], 0.65) == 1
    assert tr.last is not None and tr.last.beta == 0.65
    assert tr.sync([(0.05, 1.0)], 0.65) == 1  # the core started over
    assert len(tr.recent(0.0)) == 4


def test_sim_clock_caps_the_debt_when_the_machine_is_slow() -> None:
    clock = SimClock(max_lag_s=0.2)
    assert clock.tick(0.1, 1.0) == pytest.approx(0.1)
    clock.paid(0.1)
    assert clock.tick(10.0, 1.0) == pytest.approx(0.2)  # not 10 s of catching up
    meter = RateMeter(window_s=1.0)
    meter.add(0.0, 0.0)
    meter.add(1.0, 0.5)
    assert meter.rate == pytest.approx(0.5)


def test_readouts_say_when_the_viewer_falls_behind() -> None:
    r = Readouts(0.66, 1.0, 2.5, 0.66, "tripod", 3.0, 0.5, 1.2, 1.0, 30.0, "")
    assert "behind" in format_readouts(r)["status"]
    ok = Readouts(0.66, 1.0, 2.5, 0.66, "tripod", 3.0, 1.0, 1.2, 1.0, 30.0, "")
    assert "keeping up" in format_readouts(ok)["status"]
    err = Readouts(0.66, 1.0, None, None, "other", 3.0, None, None, 1.0, None, "", "diverged")
    assert "stopped" in format_readouts(err)["status"]


def test_svg_panels_carry_their_data() -> None:
    bars = [[(0.5, 0.8)], [], [(0.1, 0.2), (0.6, 0.9)], [], [], []]
    svg = footfall_svg(bars, 1.0, 1.0)
    assert svg.startswith("<svg") and svg.count("<rect") >= 3
    from web.footfall import D31Event

    ev = [D31Event(t, 2.0 + 0.1 * t, 0.66) for t in np.linspace(0.1, 0.9, 5)]
    d = d31_svg(ev, 1.0, 1.0, "metachronal")
    assert "metachronal" in d and "<svg" in d


def test_d31_line_breaks_where_the_angle_wraps() -> None:
    from web.footfall import D31Event

    ev = [D31Event(0.1, 6.2, 0.66), D31Event(0.2, 0.05, 0.66), D31Event(0.3, 0.1, 0.66)]
    d = d31_svg(ev, 1.0, 1.0, "other")
    assert d.count("<polyline") == 1  # 6.2 -> 0.05 is a wrap, not a line through pi
    assert d.count("<circle") == 3

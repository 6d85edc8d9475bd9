"""The paper's analysis on synthetic data with known answers, the sweep schedule, and one tiny
live sweep through the public `sweep`."""

import math

import numpy as np
import pytest

from sim_core import RunSpec, sweep
from sim_core.model.ramp import Ramp
from sim_core.paper.analysis import detect_transitions, sweep_summary

X = np.linspace(0, 2 * math.pi, 64, endpoint=False)


def test_transitions_and_hysteresis_on_a_synthetic_loop() -> None:
    down = np.linspace(0.70, 0.62, 80)
    d31_down = np.where(down > 0.645, 1.9, 2.9)
    up = down[::-1]
    d31_up = np.where(up < 0.67, 2.9, 1.9)
    t_down = detect_transitions(down, d31_down, down)
    t_up = detect_transitions(up, d31_up, up)
    assert len(t_down) == 1 and t_down[0].before == "metachronal" and t_down[0].after == "tripod"
    assert t_down[0].value == pytest.approx(0.645, abs=0.002)
    assert t_up[0].value == pytest.approx(0.67, abs=0.002)
    loop = sweep_summary(
        np.arange(160.0), np.concatenate([down, up]), np.concatenate([d31_down, d31_up]),
        start=0.70, turn=0.62, hold_s=0.0, ramp_s=80.0, beta=np.concatenate([down, up]),
        persist=4,
    )  # fmt: skip
    assert loop["width"] == pytest.approx(0.025, abs=0.003) and loop["loop"] is True


def test_isolated_blips_are_not_transitions() -> None:
    d31 = np.full(40, 1.9)
    d31[10] = 2.9
    assert detect_transitions(np.arange(40.0), d31, np.full(40, 0.66)) == []


def test_triangle_schedule() -> None:
    s = Ramp("beta", 0.70, 0.62, hold_s=1.0, ramp_s=2.0).value
    assert s(0.5) == 0.70 and s(2.0) == pytest.approx(0.66) and s(3.0) == pytest.approx(0.62)
    assert s(4.0) == pytest.approx(0.66) and s(9.0) == 0.70


def test_live_sweep_follows_its_schedule() -> None:
    r = sweep(RunSpec(beta=0.70, d31_init=2.0), parameter="beta", turn=0.66, hold_s=0.1,
              ramp_s=0.3)  # fmt: skip
    v = np.asarray(r.values)
    assert r.error is None and len(r.d31) == v.size > 4
    assert v.min() < 0.69 and v.max() == pytest.approx(0.70, abs=0.01)
    with pytest.raises(ValueError, match="cannot sweep"):
        sweep(RunSpec(), parameter="speed", turn=1.0, hold_s=0.1, ramp_s=0.1)  # type: ignore[arg-type]


def test_sweep_reports_progress() -> None:
    seen: list[float] = []
    sweep(RunSpec(beta=0.70), parameter="beta", turn=0.66, hold_s=0.1, ramp_s=0.2,
          progress=seen.append)  # fmt: skip
    assert len(seen) >= 50 and seen == sorted(seen) and 0.0 <= seen[0] < seen[-1] <= 1.0

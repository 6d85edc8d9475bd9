"""Issue 31's hypothesis tests (`lab.timing_lines`): the lines, the feature reader
on known curves, and each test's plumbing on short runs (the numbers: `insect-gait
timing-lines`, docs/REPRODUCTION.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lab import timing_lines as tl
from sim_core.model.params import ModelParams


def test_the_two_lines_cross_at_two_thirds() -> None:
    assert tl.l_dw(2 / 3) == pytest.approx(2 * math.pi / 3)
    assert tl.l_fh(2 / 3) == pytest.approx(2 * math.pi / 3)
    assert tl.l_dw(0.62) > tl.l_fh(0.62) and tl.l_dw(0.70) < tl.l_fh(0.70)
    # omega: the swing (a 1 - beta share of the cycle) lasts T_sw
    assert tl.omega(0.7) * 0.034 == pytest.approx(2 * math.pi * 0.3)


def test_features_read_a_hind_ramp_and_a_fore_bump_where_they_are() -> None:
    d = np.round(np.arange(1.4, 3.21, 0.05), 3)
    beta = 0.62
    hind = np.where(d < tl.l_dw(beta) - 0.1, 0.03, -0.03)  # ramp ends 0.1 below L_DW
    fore = -0.03 + 0.1 * np.exp(-(((d - 1.8) / 0.05) ** 2))  # a bump at 1.8
    ol = tl.OpenLoop("constraint", [beta], d.tolist(), fore[None], np.zeros((1, d.size)),
                     hind[None], np.zeros((1, d.size)))  # fmt: skip
    (f,) = tl.features(ol)
    assert f.hind_edge == pytest.approx(tl.l_dw(beta) - 0.1, abs=0.05)
    assert f.lag_ms == pytest.approx(1e3 * 0.1 / tl.omega(beta), abs=1e3 * 0.05 / tl.omega(beta))
    assert f.fore_bump_d == pytest.approx(1.8) and f.fore_bump_mrad == pytest.approx(100, abs=2)
    assert f.fore_edge is not None and 1.8 < f.fore_edge < 1.9
    assert tl.edge(d, np.full(d.size, -1.0), 0.0) is None  # never rises: no edge


def test_each_test_runs_on_short_runs() -> None:
    ol = tl.open_loop_legs(ModelParams(), [0.66], [1.9, 2.9], duration_s=0.8, settle_s=0.3,
                           phases=(0.0,))  # fmt: skip
    assert ol.hind.shape == (1, 2) and np.all(np.isfinite(ol.hind))
    (c,) = tl.chain_lags(ModelParams(), [(0.66, 1.9)], duration_s=1.0)
    assert c.final is None  # 1 s never settles by the rule
    assert c.hind_early_ms is not None and abs(c.hind_early_ms) < 34
    (r,) = tl.reduced_branches([0.66], [3.0], starts=(1.9,), duration_s=1.0)
    assert r.finals == [] and r.unsettled == 1
    assert len(tl.reduced_table([r])) == 3 and len(tl.chain_table([c])) == 3

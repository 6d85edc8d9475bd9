"""The sim_core acceptance "it walks from any initial Delta31", measured (slow: ~45 s on 2 cores).

.venv/bin/pytest -m slow tests/core/test_walking_any_start.py
"""

from __future__ import annotations

import math

import pytest

from sim_core.model.params import ModelParams, nominal_speed
from sim_core.model.runner import simulate_batch
from sim_core.model.spec import RunSpec

STARTS = [2 * math.pi * k / 12 + 0.1 for k in range(12)]


@pytest.mark.slow
@pytest.mark.parametrize("beta", [0.62, 0.70])
def test_walks_at_eq2_speed_from_every_start(beta: float) -> None:
    p = ModelParams()
    v = nominal_speed(beta, p.trajectory.stroke, p.trajectory.swing_duration) * 100.0
    runs = simulate_batch([RunSpec(beta=beta, d31_init=x, duration_s=8.0) for x in STARTS], p)
    for x, r in zip(STARTS, runs, strict=True):
        assert not r.diverged, (x, r.error)
        assert r.measures.speed_cm_s is not None and abs(r.measures.speed_cm_s - v) / v < 0.10, (
            x,
            r.measures.speed_cm_s,
            v,
        )
        assert r.measures.slip_fraction is not None and r.measures.slip_fraction < 0.10, (
            x,
            r.measures.slip_fraction,
        )

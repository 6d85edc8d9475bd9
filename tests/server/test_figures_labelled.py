"""Every job kind's REST figure says what it shows: a title and labelled axes on every panel,
the paper's numbers beside ours where the paper has them, and a stance panel that stays
readable for a long run. Drawn from results shaped as the kinds store them (no simulation)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from matplotlib.collections import LineCollection, PolyCollection

from server.figures import figure
from server.kinds import NAMES
from sim_core.contract import LEG_NAMES, PAPER

SAMPLE_DT = 0.01
LONG_RUN_S = 10.0


def _run(d0: float, duration_s: float) -> dict[str, Any]:
    """One run's whole record: Delta31 per touchdown, stance per leg, body position."""
    times = [k * SAMPLE_DT for k in range(int(duration_s / SAMPLE_DT))]
    period = 0.36
    stance = [[((t / period + 0.5 * (leg % 2)) % 1.0) < 0.62 for leg in range(6)] for t in times]
    touchdowns = [k * period for k in range(1, int(duration_s / period))]
    return {
        "d31": [d0 + (2.9 - d0) * (1 - math.exp(-t / 3)) for t in touchdowns],
        "d31_times_s": touchdowns,
        "times_s": times,
        "stance": stance,
        "body_pos_m": [[0.03 * t, 0.0, 0.01] for t in times],
    }


def _finder_rows() -> list[dict[str, Any]]:
    rows = []
    for b in (0.62, 0.64, 0.66, 0.68, 0.70):
        rows += [{"beta": b, "kind": "stable", "d31": 2.9, "gait": "tripod"},
                 {"beta": b, "kind": "stable", "d31": 1.9, "gait": "metachronal"},
                 {"beta": b, "kind": "unstable", "d31": 2.4, "gait": None}]  # fmt: skip
    return rows


CONDITIONS = {"body_mass_g": 3.0, "slope_deg": 0.0, "ground": "constraint"}
SAMPLES: dict[str, tuple[dict[str, Any], dict[str, Any]]] = {
    "run": (
        {"beta": 0.62, "duration_s": LONG_RUN_S, "d31_init": [2.0, 3.0]},
        {"runs": [_run(2.0, LONG_RUN_S), _run(3.0, LONG_RUN_S)], "series": {}},
    ),
    "return_map": (
        {"beta": 0.62, "lag": 4},
        {
            "records": [
                {"d31_n": 2.0 + 0.01 * k, "d31_n_plus_lag": 2.05 + 0.01 * k} for k in range(50)
            ],
            "lag": 4,
        },
    ),
    "sweep": (
        CONDITIONS,
        {
            "records": [
                {"beta": 0.6 + 0.01 * k, "d31_final": 2.9 if k < 6 else 1.9} for k in range(11)
            ]
        },
    ),
    "bifurcation": (CONDITIONS, {"records": _finder_rows()}),
    "hysteresis": (
        {"parameter": "beta", "start": 0.70, "turn": 0.62},
        {
            "parameter": "beta",
            "records": [
                {"leg": leg, "value": 0.62 + 0.001 * k, "d31": 2.0}
                for leg in ("first", "second")
                for k in range(80)
            ],
            "summary": {"first_leg": [{"value": 0.64}], "second_leg": [{"value": 0.68}]},
        },
    ),
    "surface": (
        {},
        {
            "records": [
                {
                    "beta": 0.62,
                    "kind": "probe",
                    "d31": 1.5 + 0.1 * k,
                    "drift": 0.01 * (2.9 - 1.5 - 0.1 * k),
                    "stable": None,
                }
                for k in range(20)
            ]
            + [{"beta": 0.62, "kind": "zero", "d31": 2.9, "drift": 0.0, "stable": True}]
        },
    ),
    "atlas": (
        {"axis": "mass"},
        {
            "records": [
                {"beta": b, "value": v, "region": "both"}
                for b in (0.6, 0.65, 0.7)
                for v in (2.0, 3.0)
            ]
        },
    ),
}


def test_every_kind_has_a_sample() -> None:
    assert set(SAMPLES) == set(NAMES)


@pytest.mark.parametrize("kind", NAMES)
def test_every_panel_has_a_title_and_labelled_axes(kind: str) -> None:
    fig = figure(kind, *SAMPLES[kind])
    assert fig.axes
    for ax in fig.axes:
        assert ax.get_title().strip(), f"{kind}: a panel without a title"
        assert ax.get_xlabel().strip() and ax.get_ylabel().strip(), f"{kind}: unlabelled axes"


def _legend_texts(fig: Any) -> str:
    return " ".join(t.get_text() for ax in fig.axes if ax.get_legend()
                    for t in ax.get_legend().get_texts())  # fmt: skip


@pytest.mark.parametrize("kind", ["bifurcation", "sweep", "hysteresis", "atlas"])
def test_the_papers_transitions_stand_beside_ours_marked_as_the_papers(kind: str) -> None:
    fig = figure(kind, *SAMPLES[kind])
    ax = fig.axes[0]
    xs = [np.asarray(line.get_xdata(), dtype=float) for line in ax.get_lines()]
    verticals = {round(float(x[0]), 6) for x in xs if len(x) and np.ptp(x) == 0}
    assert {PAPER.transition_down, PAPER.transition_up} <= verticals
    assert f"paper: transitions β {PAPER.transition_down:g}" in _legend_texts(fig)


def test_the_bifurcation_figure_draws_fig_8s_stable_ranges() -> None:
    fig = figure("bifurcation", *SAMPLES["bifurcation"])
    bands = [c for c in fig.axes[0].collections if isinstance(c, LineCollection)]
    segments = {tuple(map(tuple, s.round(6))) for c in bands for s in c.get_segments()}
    (lo, hi), d = PAPER.tripod_stable, PAPER.branch_tripod_rad
    assert ((lo, d), (hi, d)) in segments
    (lo, hi), d = PAPER.metachronal_stable, PAPER.branch_metachronal_rad
    assert ((lo, d), (hi, d)) in segments
    assert "paper, Fig. 8: tripod stable" in _legend_texts(fig)


def test_a_long_runs_stance_panel_shows_its_last_second_and_says_so() -> None:
    fig = figure("run", *SAMPLES["run"])
    stance = next(ax for ax in fig.axes if ax.get_title().startswith("stance"))
    assert "last 1 s" in stance.get_title()
    lo, hi = stance.get_xlim()
    assert hi - lo == pytest.approx(1.0, abs=2 * SAMPLE_DT) and hi > LONG_RUN_S - 0.1
    bars = [c for c in stance.collections if isinstance(c, PolyCollection)]
    assert len(bars) == len(LEG_NAMES)
    # ~3 gait cycles of 0.36 s in the window: a few bars per leg, not one solid bar
    per_leg = [len(b.get_paths()) for b in bars]
    assert all(2 <= n <= 4 for n in per_leg), per_leg

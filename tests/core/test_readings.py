"""Issue 31's readings screen: each reading is an option that changes walking, the screen's
census counts every run once and reads repeated runs from the cache."""

from __future__ import annotations

from pathlib import Path

import pytest

from lab.readings import (
    READINGS,
    find_states,
    finder_table,
    screen,
    settings_name,
    table,
    variants,
)
from sim_core import ModelParams, RunSpec, simulate
from sim_core.contract.finder import FinderConfig
from sim_core.runs.backends import InlineBackend
from sim_core.runs.cache import ResultCache


def test_a_reading_changes_the_walk_and_ours_is_the_default() -> None:
    assert READINGS["ours"] == {}
    spec = RunSpec(beta=0.66, d31_init=2.0, duration_s=0.6)
    base = simulate(spec)
    late = simulate(spec, ModelParams.of(**READINGS["late descent"]))
    assert base.failure is None and late.failure is None
    assert (
        base.events.d31.tolist() != late.events.d31.tolist()
    )  # feet that land late now land sooner
    assert (
        late.measures.landing_swing_share is not None
        and base.measures.landing_swing_share is not None
    )
    assert late.measures.landing_swing_share < base.measures.landing_swing_share


def test_the_census_counts_every_start_and_reads_repeats_from_the_cache(tmp_path: Path) -> None:
    cache = ResultCache(tmp_path)
    first = screen("ours", "penalty", [0.66], cache, InlineBackend(), duration_s=1.0, starts=2,
                   progress=False)  # fmt: skip
    (c,) = first
    settled = sum(n for _, n, _ in c.states)
    assert settled + len(c.unsettled) + c.failed == 2
    assert len(table(first)) == 3
    again = screen("ours", "penalty", [0.66], cache, InlineBackend(), duration_s=1.0, starts=2,
                   progress=False)  # fmt: skip
    assert again == first
    with pytest.raises(ValueError, match="unknown reading"):
        screen("nope", "penalty", [0.66], cache, InlineBackend())


def test_a_lever_screened_under_a_reading_is_named_and_used(tmp_path: Path) -> None:
    """`over` (the CLI's --params) reaches the runs and names the census."""
    cache = ResultCache(tmp_path)
    kw = {"duration_s": 1.0, "starts": 1, "progress": False}
    base = screen("ours", "penalty", [0.66], cache, InlineBackend(), **kw)
    (c,) = screen("ours", "penalty", [0.66], cache, InlineBackend(),
                  over={"support_ratio": 2.0}, **kw)  # fmt: skip
    assert c.reading == "ours, support_ratio 2"
    assert c.landing is not None and base[0].landing is not None
    assert c.landing != base[0].landing  # stiffer middle legs: the walk changed


def test_the_finder_reads_a_setting_and_its_table_counts_each_beta(tmp_path: Path) -> None:
    """`readings --finder`: the reproduction's finder on a reading plus a lever (quick sizes:
    the machinery, not science), one table row per beta, and repeats read from the cache."""
    cache = ResultCache(tmp_path)
    kw = {"over": {"com_offset_x": -1e-3}, "cfg": FinderConfig.quick(), "progress": False}
    cells = find_states("ours", "penalty", [0.62, 0.70], cache, InlineBackend(), **kw)
    assert [c.beta for c in cells] == [0.62, 0.70]
    assert all(c.runs for c in cells)
    rows = finder_table(settings_name("ours", kw["over"]), "penalty", cells)
    assert len(rows) == 4 and rows[2].startswith("| ours, com_offset_x -0.001 | penalty | 0.62 |")
    again = find_states("ours", "penalty", [0.62, 0.70], cache, InlineBackend(), **kw)
    assert again == cells


def test_the_robustness_variants_scale_the_settings_own_values() -> None:
    """--robust: the setting first, then each calibrated parameter at 0.9x and 1.1x of its
    value under the setting (a lever's value, not the default's), the lever kept."""
    from sim_core.paper.claims import CALIBRATED

    over = {"com_offset_x": -1e-3, "support_ratio": 2.0}
    vs = variants("ours", "penalty", over)
    assert vs[0] == over and len(vs) == 1 + 2 * len(CALIBRATED)
    assert {"com_offset_x": -0.9e-3, "support_ratio": 2.0} in [
        {k: pytest.approx(v) for k, v in x.items()} for x in vs
    ]
    stand = ModelParams().trajectory.stand_height
    assert [x["stand_height"] for x in vs if "stand_height" in x] == pytest.approx(
        [0.9 * stand, 1.1 * stand]
    )
    assert all(x["support_ratio"] == 2.0 for x in vs)

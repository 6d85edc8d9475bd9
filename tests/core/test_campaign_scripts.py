"""The campaigns' scripts are code (issue 29): each imports against today's core (two of them
imported a removed `gait.tail_drift` while they lived in docs/), and none reaches into the
runner module or the import path."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest

import lab.campaigns as campaigns

NAMES = [m.name for m in pkgutil.iter_modules(campaigns.__path__)]


def test_every_campaign_is_found() -> None:
    assert {"gait_campaign2", "gait_campaign3", "ground_respelled"} <= set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_a_campaign_imports_and_has_a_main(name: str) -> None:
    mod = importlib.import_module(f"lab.campaigns.{name}")
    assert callable(getattr(mod, "main", None))
    source = inspect.getsource(mod)
    assert "sys.path" not in source and "runner_mod." not in source


def test_the_border_sweeps_go_through_the_result_cache(tmp_path) -> None:
    """campaign 3's triangle sweeps are `sim_core.runs` tasks: cached by content, on any
    backend, so a rerun simulates nothing."""
    from lab.campaigns.gait_campaign3 import border_sweeps
    from sim_core.runs.backends import InlineBackend
    from sim_core.runs.cache import ResultCache

    jobs = [({}, 0.64, 0.66, 0.1, 0.1, "up")]  # 0.2 s each way, held 0.1 s
    cache = ResultCache(tmp_path)
    (sw,) = border_sweeps(jobs, InlineBackend(), cache)
    assert sw["error"] is None and sw["direction"] == "up" and len(sw["d31"]) > 2
    assert len(sw["values"]) == len(sw["d31"]) and max(sw["values"]) > 0.65
    assert len(list(tmp_path.glob("*.json"))) == 1
    again = border_sweeps(jobs, InlineBackend(), ResultCache(tmp_path))
    assert again == [sw]


def test_the_atlas_comparison_names_each_changed_cell() -> None:
    """`atlas_short_probes.compare` lists the cells whose region (or decidedness) differ, and
    refuses atlases whose cells are not in the same order."""
    from lab.campaigns.atlas_short_probes import committed, compare

    before = committed("mass")
    assert compare(before, before) == []
    points = list(before.points)
    cell = points[5]
    other = "tripod only" if cell.region != "tripod only" else "metachronal only"
    points[5] = cell.model_copy(update={"region": other})
    diffs = compare(before, before.model_copy(update={"points": points}))
    assert [(d["beta"], d["value"]) for d in diffs] == [(cell.beta, cell.value)]
    assert diffs[0]["after"]["region"] == other  # type: ignore[index]
    shuffled = before.model_copy(update={"points": points[::-1]})
    with pytest.raises(ValueError, match="same order"):
        compare(before, shuffled)

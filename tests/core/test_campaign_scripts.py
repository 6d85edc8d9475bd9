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

"""The campaigns' scripts are code (issue 29): each imports against today's core (two of them
imported a removed `gait.tail_drift` while they lived in docs/), and none reaches into the
runner module or the import path."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest

import sim_core.studies.campaigns as campaigns

NAMES = [m.name for m in pkgutil.iter_modules(campaigns.__path__)]


def test_every_campaign_is_found() -> None:
    assert {"gait_campaign2", "gait_campaign3", "ground_respelled"} <= set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_a_campaign_imports_and_has_a_main(name: str) -> None:
    mod = importlib.import_module(f"sim_core.studies.campaigns.{name}")
    assert callable(getattr(mod, "main", None))
    source = inspect.getsource(mod)
    assert "sys.path" not in source and "runner_mod." not in source

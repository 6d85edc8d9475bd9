"""Named model settings (sim_core/model/settings.py): validated, invented leaves only, and the
soft-leg regime is what its name says (feet land early in the swing, docs/studies/soft_legs.md)."""

from __future__ import annotations

from types import MappingProxyType

import pytest

from sim_core import RunSpec, simulate
from sim_core.model import settings
from sim_core.model.params import ModelParams
from sim_core.model.settings import SOFT_LEGS, named_params


def test_a_named_setting_is_its_leaves_with_overrides_on_top() -> None:
    p = named_params("soft_legs", support_ratio=2.0)
    assert all(p.leaf(k) == v for k, v in SOFT_LEGS.items())
    assert p.leaf("support_ratio") == 2.0 and p.leaf("body_mass") == ModelParams().leaf("body_mass")
    with pytest.raises(ValueError, match="no model setting 'stiff'; known: soft_legs"):
        named_params("stiff")


def test_a_setting_that_touches_a_paper_parameter_is_refused(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(settings, "NAMED_SETTINGS", MappingProxyType({"x": {"body_mass": 1e-3}}))
    with pytest.raises(ValueError, match="body_mass is not an invented parameter"):
        settings._only_invented()


def test_soft_legs_land_early_and_the_defaults_do_not() -> None:
    spec = RunSpec(beta=0.66, d31_init=2.0, duration_s=6.0)
    soft = simulate(spec, named_params("soft_legs")).measures.landing_swing_share
    stiff = simulate(spec).measures.landing_swing_share
    assert soft < 0.97 < 0.99 <= stiff, (soft, stiff)

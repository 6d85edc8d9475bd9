"""The instruments' outputs record their protocol typed (`config`: the finder's `FinderConfig`, a
finder atlas's `AtlasGrid`, the surface's `SurfaceConfig`, a surface atlas's
`SurfaceAtlasConfig`), and every committed result file still loads, its protocol serialised
to the same JSON it holds: the same keys, in the same order, with the same values.

A file written before an option existed reads as it ran (the finder atlases of
docs/figures: no kicks, no neighbour seeds), not with today's default.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

import pytest
from pydantic import BaseModel, ValidationError

from sim_core.contract import (
    AtlasOutput,
    DriftSurface,
    FinderConfig,
    FinderOutput,
    SurfaceAtlas,
    SurfaceConfig,
)
from sim_core.contract.finder import BEFORE_THE_OPTION, AtlasGrid
from sim_core.contract.surface import SurfaceAtlasConfig, WalkConfig

REPO = Path(__file__).resolve().parents[2]
OUTPUTS: tuple[type[BaseModel], ...] = (FinderOutput, AtlasOutput, DriftSurface, SurfaceAtlas)
CONFIG_TYPE: dict[type[BaseModel], type[Any]] = {
    FinderOutput: FinderConfig,
    AtlasOutput: AtlasGrid,
    DriftSurface: SurfaceConfig,
    SurfaceAtlas: SurfaceAtlasConfig,
}


def _result_files() -> list[Path]:
    """Every committed JSON file that is an instrument's output (a top-level `config` beside
    the cells or probes it describes)."""
    out = []
    for path in sorted((REPO / "docs").rglob("*.json")):
        data = json.loads(path.read_text())
        if isinstance(data, dict) and "config" in data and {"cells", "points"} & set(data):
            out.append(path)
    return out


FILES = _result_files()


def _load(path: Path) -> BaseModel:
    text = path.read_text()
    errors = []
    for model in OUTPUTS:
        try:
            return model.model_validate_json(text)
        except ValidationError as exc:
            errors.append(f"{model.__name__}: {exc.errors()[0]}")
    raise AssertionError(f"{path.name} is none of the outputs: {errors}")


def test_the_committed_outputs_are_found() -> None:
    names = {p.name for p in FILES}
    assert {"bifurcation.json", "surface.json", "atlas_mass.json",
            "surface_atlas_mass_constraint.json", "surface_soft_legs.json"} <= names  # fmt: skip


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_a_committed_output_loads_with_its_protocol_typed_and_dumped_as_it_is(path: Path) -> None:
    loaded = _load(path)
    config = loaded.config  # type: ignore[attr-defined]  # every output has one
    assert type(config) is CONFIG_TYPE[type(loaded)]
    stored = json.loads(path.read_text())["config"]
    dumped = json.loads(loaded.model_dump_json())["config"]
    if isinstance(loaded, AtlasOutput) and set(BEFORE_THE_OPTION) - set(stored["finder"]):
        # searched before the finder kicked its states or lent seeds: read as it ran
        assert {k: getattr(config.finder, k) for k in BEFORE_THE_OPTION} == BEFORE_THE_OPTION
        stored["finder"] = dumped["finder"] | stored["finder"]
    assert json.dumps(dumped) == json.dumps(stored)  # keys, order, values: as written


def test_a_surface_atlas_not_walked_records_no_walks() -> None:
    cfg = SurfaceAtlasConfig.of(SurfaceConfig(), refine=False, walks=None)
    walked = dataclasses.replace(cfg, walks=WalkConfig())
    surface_fields = [f.name for f in dataclasses.fields(SurfaceConfig)]
    for c in (cfg, walked):
        atlas = SurfaceAtlas(axis="mass", param="body_mass_g", ground="constraint", betas=[],
                             values=[], points=[], folds=[], sim_s=0.0, config=c)  # fmt: skip
        dumped = json.loads(atlas.model_dump_json())["config"]
        assert list(dumped)[: len(surface_fields)] == surface_fields
        assert ("walks" in dumped) == (c.walks is not None)
        assert SurfaceAtlas.model_validate_json(atlas.model_dump_json()).config == c


def test_an_unknown_protocol_key_is_refused() -> None:
    """A key no protocol declares is a misspelling or another instrument's, not data."""
    with pytest.raises(ValidationError, match="floor_rads"):
        DriftSurface.model_validate({"config": {"floor_rads": 3e-4}, "betas": [], "points": [],
                                     "zeros": [], "near_zeros": [], "branches": [],
                                     "folds": [], "sim_s": 0.0, "body_mass_g": 3.0,
                                     "slope_deg": 0.0, "ground": "constraint"})  # fmt: skip

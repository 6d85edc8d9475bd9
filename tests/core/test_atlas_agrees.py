"""The README's headline point, read three ways: at beta 0.62, 3 g, today's contact
("constraint" ground), the atlas's cell (surface plus deciding walks, as `insect-gait atlas`
computes it), the drift-surface panel's file (docs/figures/surface.json) and a settled walk
from Delta31 = 3.0 name the same stable gaits (issue 55, D2). Since reproduce's short probes
(issue 54) the panel's surface leaves the tripod's narrow pair at 0.62 in a near-zero band
(it cannot tell there, and says so) and reproduce's own walks decide it (issue 52, point 1:
docs/figures/fig8.json's cells): a gait the panel lacks must lie where it cannot tell."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

from sim_core.contract.surface import DriftSurface, SurfaceConfig
from sim_core.model.gait import classify_gait, settling
from sim_core.model.params import ModelParams
from sim_core.model.runner import simulate
from sim_core.model.spec import RunSpec
from sim_core.paper.surface_atlas import surface_atlas
from sim_core.paper.surface_walks import WalkConfig, window_zeros
from sim_core.runs.cache import ResultCache

SURFACE_JSON = Path(__file__).resolve().parents[2] / "docs" / "figures" / "surface.json"
BETA = 0.62


def _cannot_tell(surface: DriftSurface, beta: float) -> list[tuple[float, float]]:
    """Where the panel's surface cannot tell at `beta`: its unresolved zeros' brackets and its
    near-zero bands."""
    spans = [(z.lo, z.hi) for z in surface.zeros_at(beta) if not z.resolved]
    return spans + [(n.lo, n.hi) for n in surface.near_zeros if abs(n.beta - beta) < 1e-9]


def _agrees(gaits: set[str], stable: list[float], surface: DriftSurface) -> bool:
    """The panel names the same gaits, or each it lacks sits where it cannot tell."""
    panel = {classify_gait(z.d31, BETA) for z in window_zeros(surface, BETA) if z.stable}
    spans = _cannot_tell(surface, BETA)
    missing = [x for x in stable if classify_gait(x, BETA) not in panel]
    return panel <= gaits and all(any(a - 0.03 <= x <= b + 0.03 for a, b in spans)
                                  for x in missing)  # fmt: skip


@pytest.mark.slow
def test_atlas_surface_and_a_walk_from_3_name_the_same_gaits_at_beta_062(tmp_path: Path) -> None:
    surface = DriftSurface.model_validate_json(SURFACE_JSON.read_text())
    assert (surface.body_mass_g, surface.slope_deg, surface.ground) == (3.0, 0.0, "constraint")
    panel = {classify_gait(z.d31, BETA) for z in window_zeros(surface, BETA) if z.stable}

    # the atlas's cell as the `atlas` command computes it: no band pass, walks on
    atlas = surface_atlas(
        "mass",
        [BETA],
        [3.0],
        cache=ResultCache(tmp_path),
        config=replace(SurfaceConfig(), band_pass=False),
        params=ModelParams.of(ground="constraint"),
        walks=WalkConfig(),
        progress=False,
    )
    (cell,) = atlas.points
    assert cell.checked and not cell.undecided, [w.why for w in cell.walks]

    walk = simulate(RunSpec(beta=BETA, d31_init=3.0, duration_s=WalkConfig().duration_s))
    settled = settling(walk.events.d31)
    assert settled.settled and settled.final is not None, settled.why
    gait = classify_gait(settled.final, BETA)

    assert _agrees(set(cell.gaits), cell.stable, surface), (cell, panel)
    assert gait in cell.gaits and gait == "tripod"
    # the walk's state is one the atlas lists (within the finder's one-attractor distance)
    assert any(abs(x - settled.final) <= 0.05 for x in cell.stable), (cell.stable, settled)


def test_the_committed_atlas_the_surface_panel_and_a_walk_from_3_agree_at_beta_062() -> None:
    """The files the viewer's panels draw (not recomputed): the constraint ground's mass atlas
    at (0.62, 3 g), surface.json at 0.62, and a settled walk from 3.0 name the same gaits."""
    from sim_core.contract.surface import SurfaceAtlas

    atlas = SurfaceAtlas.model_validate_json(
        (SURFACE_JSON.parent / "surface_atlas_mass_constraint.json").read_text()
    )
    (cell,) = [p for p in atlas.points if abs(p.beta - BETA) < 1e-9 and p.value == 3.0]
    surface = DriftSurface.model_validate_json(SURFACE_JSON.read_text())
    assert _agrees(set(cell.gaits), cell.stable, surface) and not cell.undecided, cell
    # reproduce's cell at 0.62, decided by its own walks, names the atlas's gaits
    fig8 = json.loads((SURFACE_JSON.parent / "fig8.json").read_text())["data"]["cells"]
    (decided,) = [c for c in fig8 if abs(c["beta"] - BETA) < 1e-9]
    assert set(decided["gaits"]) == set(cell.gaits), (decided, cell)

    walk = simulate(
        RunSpec(beta=BETA, d31_init=3.0, duration_s=WalkConfig().duration_s,
                stop_if_settled_s=WalkConfig().try_s)
    )  # fmt: skip
    settled = settling(walk.events.d31)
    assert settled.settled and settled.final is not None, settled.why
    assert classify_gait(settled.final, BETA) in cell.gaits
    assert any(abs(x - settled.final) <= 0.05 for x in cell.stable), (cell.stable, settled)
    assert any(abs(x - settled.final) <= 0.05 for x in decided["stable"]), decided

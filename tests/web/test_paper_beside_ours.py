"""The paper's numbers on the viewer's panels, where the paper has a number: its transition
betas (Fig. 6a) on every beta axis, its Fig. 8 stable ranges on the bifurcation panel, each
marked as the paper's in the legend; and the atlas's ticks, one per row."""

from __future__ import annotations

import re

import pytest

from sim_core.contract import PAPER
from tests.web.test_svg_legible import PANELS
from web.atlas_svg import row_position

PAPER_BETAS = {f"{PAPER.transition_down:g}", f"{PAPER.transition_up:g}"}


def _verticals(svg: str) -> dict[str, str]:
    """The paper's dashed verticals: beta -> the ramp direction that meets it."""
    return dict(re.findall(r'class="paper" data-beta="([\d.]+)" data-direction="(\w+)"', svg))


@pytest.mark.parametrize(
    "name", ["bifurcation", "surface", "atlas mass constraint", "atlas slope penalty", "ramp beta"]
)
def test_every_beta_axis_shows_the_papers_transitions(name: str) -> None:
    svg = PANELS[name]
    assert _verticals(svg) == {
        f"{PAPER.transition_down:g}": "down",
        f"{PAPER.transition_up:g}": "up",
    }
    assert f"paper: β {PAPER.transition_down:g} ↓ {PAPER.transition_up:g} ↑" in svg or (
        f"paper, Fig. 6a: β {PAPER.transition_down:g}" in svg
    )


def test_a_ramp_of_another_parameter_has_no_paper_betas() -> None:
    assert not _verticals(PANELS["ramp body_mass_g"]) and "paper" not in PANELS["ramp slope_deg"]


def test_the_ramp_panel_colours_the_papers_transitions_as_its_directions() -> None:
    from web.style import RAMP_COLOURS

    svg = PANELS["ramp beta"]
    for direction in ("down", "up"):
        assert re.search(
            f'class="paper"[^>]*data-direction="{direction}"[^>]*stroke="{RAMP_COLOURS[direction]}"',
            svg,
        )


def test_the_bifurcation_panel_draws_fig_8s_ranges_at_the_branches() -> None:
    svg = PANELS["bifurcation"]
    ranges = re.findall(r'class="paper-range" data-gait="(\w+)"[^>]*><title>([^<]*)</title>', svg)
    assert [g for g, _ in ranges] == ["tripod", "metachronal"]
    lo, hi = PAPER.tripod_stable
    assert f"β {lo:g} to {hi:g} (Δ31 {PAPER.branch_tripod_rad:g} rad)" in ranges[0][1]
    assert "paper: Fig. 8 stable ranges" in svg and ">paper</text>" in svg


def test_the_atlas_labels_every_row() -> None:
    svg = PANELS["atlas mass constraint"]
    cells = re.findall(r'<rect class="cell"[^>]*y="([\d.]+)"[^>]*height="([\d.]+)"', svg)
    heights = {round(float(h), 1) for _, h in cells}
    assert len(heights) == 1  # rows of one height, whatever the values' spacing
    rows = {round(float(y), 1) for y, _ in cells}
    ticks = re.findall(r'text-anchor="end">([\d.−-]+)</text>', svg)
    assert len(ticks) == len(rows) == 8  # surface_atlas_mass_constraint.json: 8 masses
    assert [float(t) for t in ticks] == sorted(float(t) for t in ticks)


def test_the_live_point_sits_between_the_rows_of_its_neighbours() -> None:
    values = [1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0]
    assert row_position(values, 1.0) == 0.5 and row_position(values, 8.0) == 6.5
    assert row_position(values, 5.0) == pytest.approx(5.0)  # halfway from 4 (4.5) to 6 (5.5)
    assert row_position(values, 0.2) == 0.0 and row_position(values, 9.0) == 7.0  # the edges

"""The viewer's new panels and exports, pure: the finder's bifurcation points, the gait atlas,
the drift surface, the return map, the whole-run Delta31 record, stance intervals, CSV/JSON
exports, job bodies."""

from __future__ import annotations

import csv
import html
import io
import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from sim_core.contract import (
    TWO_PI,
    DriftSurface,
    EventConditions,
    FinderOutput,
    ModelChoice,
    SurfaceAtlas,
)
from web import controls, export
from web.atlas_svg import atlas_svg
from web.bifurcation import WatchedFile, finder_points, load_validated
from web.bifurcation_svg import bifurcation_svg
from web.d31_svg import d31_svg
from web.record import D31Event, d31_since, stance_intervals
from web.return_map_plot import RECENCY_SHADES, SERIES, return_map_data
from web.surface_cells import drift_colour, drift_level
from web.surface_svg import surface_svg
from web.svg import MAX_DRAWN, n_dots

MADE = export.made_by(ModelChoice())  # the default model's: what every export carries


def _run(d31_init: float, final: float | None, settled: bool, attractor: int | None) -> dict:
    return {
        "d31_init": d31_init, "duration_s": 40.0, "final": final, "drift": 0.0001,
        "settled": settled, "why": "" if settled else "drifts", "attractor": attractor,
    }  # fmt: skip


def _cell(beta: float, mass: float = 3.0, slope: float = 0.0, **kw: Any) -> dict[str, Any]:
    attractors = kw.get("attractors", [(2.95, "tripod"), (1.75, "metachronal")])
    return {
        "beta": beta, "body_mass_g": mass, "slope_deg": slope,
        "attractors": [
            {"d31": d, "lo": d - 0.01, "hi": d + 0.01, "gait": g, "starts": 3, "runs": 4,
             "slope": 0.5, "slope_pairs": 10, "max_drift": 1e-4}
            for d, g in attractors
        ],
        "borders": kw.get("borders", [
            {"below": 0, "above": 1, "start_lo": 2.3, "start_hi": 2.32, "resolved": True,
             "d31": 2.4, "slope": 1.4, "steps": 6}
        ]),
        "ghosts": kw.get("ghosts", [{"d31": 2.6, "drift": 0.001, "cycles": 40, "d31_init": 3.1}]),
        "runs": kw.get("runs", [_run(0.0, 1.75, True, 1), _run(3.9, 4.4, False, None)]),
        "sim_s": 400.0,
    }  # fmt: skip


def _finder() -> FinderOutput:
    return FinderOutput.model_validate(
        {"source": "test", "config": {}, "cells": [_cell(0.62), _cell(0.70, attractors=[
            (1.8, "metachronal"), (4.0, "other")])]}
    )  # fmt: skip


def test_a_finder_output_draws_each_kind_of_point(tmp_path: Path) -> None:
    path = tmp_path / "bifurcation.json"
    path.write_text(_finder().model_dump_json())
    finder, note = load_validated(path, FinderOutput, "finder results")
    assert finder is not None and note == ""
    pts = finder_points(finder)
    assert len(pts.stable) == 4 and len(pts.unstable) == 2 and len(pts.ghosts) == 2
    assert pts.unsettled == [(0.62, 4.4), (0.70, 4.4)]  # finals of the runs that did not settle
    svg = bifurcation_svg(pts, note, [], (0.66, 2.0), (0.55, 0.80))
    assert svg.count('class="stable"') == 4
    assert svg.count('class="unstable"') == 2 and 'fill="#fff"' in svg  # open circles
    assert svg.count('class="ghost"') == 2 and svg.count('class="unsettled"') == 2
    # coloured by gait: tripod orange, metachronal green, other grey
    for colour in ("#ff7f0e", "#2ca02c", "#7f7f7f"):
        assert re.search(f'class="stable"[^>]*fill="{colour}"', svg), colour
    assert 'class="live"' in svg and 'class="note"' not in svg


@pytest.mark.parametrize(
    ("content", "says"),
    [
        (None, "absent"),
        ("{not json", "bifurcation.json is not a FinderOutput: (top level): Invalid JSON"),
        ('{"source": "x", "points": []}', "is not a FinderOutput: config: Field required"),
    ],
)
def test_a_missing_or_invalid_file_gives_a_one_line_note(
    tmp_path: Path, content: str | None, says: str
) -> None:
    path = tmp_path / "bifurcation.json"
    if content is not None:
        path.write_text(content)
    finder, note = load_validated(path, FinderOutput, "finder results")
    assert finder is None and says in note and "\n" not in note
    svg = bifurcation_svg(None, note, [], (0.66, None), (0.55, 0.80))
    assert 'class="note"' in svg and 'class="stable"' not in svg


def test_the_watched_file_rereads_when_it_changes(tmp_path: Path) -> None:
    path = tmp_path / "bifurcation.json"
    w = WatchedFile(path, FinderOutput, "finder results")
    assert w.get()[0] is None
    path.write_text(_finder().model_dump_json())
    assert w.get()[0] is not None
    seen = w.version
    w.get()
    assert w.version == seen  # unchanged file: same object, same version (no redraw)


def _atlas() -> SurfaceAtlas:
    betas, values = [0.60, 0.65, 0.70], [2.0, 3.0]
    regions = [["both", "tripod only", "metachronal only"], ["other states", "none", "both"]]
    points = [
        {
            "beta": b,
            "value": v,
            "stable": [],
            "gaits": [],
            "unresolved": int(r == "both"),
            "region": r,
        }
        for v, row in zip(values, regions, strict=True)
        for b, r in zip(betas, row, strict=True)
    ]
    return SurfaceAtlas.model_validate({
        "axis": "mass", "param": "body_mass_g", "ground": "constraint", "betas": betas,
        "values": values, "points": points, "folds": [], "sim_s": 0.0, "config": {},
    })  # fmt: skip


def test_the_atlas_draws_a_cell_per_condition_coloured_by_region() -> None:
    svg = atlas_svg(_atlas(), "", "mass", "body mass (g)", (0.66, 2.4), (0.55, 0.80))
    assert svg.count('class="cell"') == 6
    # the two "both" cells had an unresolved zero in the window: drawn faint, said in the title
    assert svg.count('data-unresolved="true"') == 2 and "(unresolved zeros here)" in svg
    for region in ("both", "tripod only", "metachronal only", "other states", "none"):
        assert f'data-region="{region}"' in svg
    assert 'class="live" data-inside="true"' in svg
    outside = atlas_svg(_atlas(), "", "mass", "body mass (g)", (0.66, 9.0), (0.55, 0.80))
    assert 'data-inside="false"' in outside
    none = atlas_svg(None, "no atlas: /x/atlas_slope.json absent", "slope", "slope", (0.6, 0),
                     (0.55, 0.80))  # fmt: skip
    assert 'class="note"' in none and "absent" in none and 'class="cell"' not in none


def test_the_whole_runs_d31_events_draw_a_bounded_number() -> None:
    core = [(0.1 * k, 2.0 + 0.001 * k) for k in range(5000)]  # 500 s of the core's touchdowns
    assert [t for t, _ in d31_since(core, 499.75)] == pytest.approx([499.8, 499.9])
    whole = d31_svg(core, 500.0, None, "metachronal")
    assert "whole run" in whole and 'data-t0="0.000"' in whole and 'data-n-events="5000"' in whole
    assert n_dots(whole) <= MAX_DRAWN and "1 in 5 drawn" in whole
    last = d31_svg(d31_since(core, 470.0), 500.0, 30.0, "metachronal")
    assert "last 30 s" in last and 'data-t0="470.000"' in last


def test_the_footfall_export_is_the_records_stance_intervals() -> None:
    t = np.arange(10) * 0.1
    s = np.zeros((10, 6), bool)
    s[2:5, 0] = True  # R1 in stance from 0.2 to 0.5
    s[7:, 0] = True  # and from 0.7, still on at the end
    s[:, 3] = True  # L2 always
    now = EventConditions(0.66, 3.0, 0.0)
    text = export.footfall_csv(stance_intervals(t, s), [], now, made=MADE).decode()
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0][:3] == ["leg", "start_s", "end_s"]
    assert [r[:3] for r in rows[1:]] == [["L2", "0.0", "0.9"], ["R1", "0.2", "0.5"],
                                         ["R1", "0.7", "0.9"]]  # fmt: skip


def _settings(**kw: Any) -> export.Settings:
    from sim_core.contract import RunTemplate

    run = RunTemplate(body_mass_g=kw.pop("body_mass_g", 3.0), slope_deg=kw.pop("slope_deg", 0.0))
    base = dict(run=run, beta=0.66, d31_init=2.09, speed=1.0, time_s=12.0, ramp=None,
                ramp_running=False, ramp_started_at_s=None)  # fmt: skip
    return export.Settings(**{**base, **kw})


def test_the_exports_carry_the_records() -> None:
    def down(k: int) -> EventConditions:
        return EventConditions(0.70 - 0.001 * k, 3.0 + 0.015 * k, 0.41 * k, ramp="down",
                               ramp_param="beta")  # fmt: skip

    ev = [D31Event(0.1 * k, 2.0, down(k)) for k in range(5)]
    rows = list(csv.DictReader(io.StringIO(export.d31_csv(ev, made=MADE).decode())))
    assert [float(r["beta"]) for r in rows] == pytest.approx([0.70, 0.699, 0.698, 0.697, 0.696])
    assert rows[0].keys() == set(export.D31_COLUMNS) and rows[0]["ramp"] == "beta down"
    # a ramp's continuous values are written to their resolution, not as float noise
    assert [r["body_mass_g"] for r in rows] == ["3.0", "3.015", "3.03", "3.045", "3.06"]
    assert [r["slope_deg"] for r in rows] == ["0.0", "0.41", "0.82", "1.23", "1.64"]
    ramp = controls.make_ramp("beta", 0.70, 0.62, 0.0, 8.0)
    rows = list(csv.DictReader(io.StringIO(export.ramp_csv(ev, ramp, 0.0, made=MADE).decode())))
    assert float(rows[-1]["scheduled"]) == pytest.approx(0.70 - 0.08 * 0.4 / 8.0)  # t = 0.4 s
    js = json.loads(export.settings_json(_settings(ramp=ramp), made=MADE))
    assert js["ramp"]["param"] == "beta" and js["jobs"]["hysteresis"]["ramp"]["turn"] == 0.62
    assert js["jobs_url"] == "http://127.0.0.1:8000/v1/jobs"
    assert (
        js["speed"] == 1.0
        and json.loads(export.settings_json(_settings(speed=None), made=MADE))["speed"] == "max"
    )


def test_the_job_bodies_are_what_the_api_accepts() -> None:
    from server.kinds import JOB_SPEC_ADAPTER

    ramp = controls.make_ramp("body_mass_g", 3.0, 6.0, 5.0, 30.0)
    jobs = export.jobs(_settings(beta=0.62, slope_deg=-7.5, ramp=ramp))
    run = JOB_SPEC_ADAPTER.validate_python(jobs["run"])
    assert run.kind == "run" and run.beta == 0.62 and run.slope_deg == -7.5  # type: ignore[union-attr]
    hyst = JOB_SPEC_ADAPTER.validate_python(jobs["hysteresis"])
    assert hyst.kind == "hysteresis" and hyst.ramp == ramp  # type: ignore[union-attr]
    assert "hysteresis" not in export.jobs(_settings())
    line = export.curl("http://h:1/", jobs["run"])
    assert line.startswith("curl -s -X POST http://h:1/v1/jobs ") and '"kind": "run"' in line


def test_the_return_map_and_the_status_box() -> None:
    from web.readouts import status_html

    # uPlot's aligned series: x sorted (with the diagonal's ends 0 and 2 pi), one column per
    # age group, NaN where the pair is another group's; newest pairs in the last group
    pairs = [(3.0, 3.1), (1.0, 1.2), (2.0, 2.05)] * 4  # 12 pairs, 2 per age group
    x, diag, *groups = return_map_data(pairs)
    assert len(groups) == RECENCY_SHADES and len(SERIES) == 2 + RECENCY_SHADES
    assert x[0] < 0.0 and x[-1] > TWO_PI and (np.diff(x) >= 0).all()  # past both ends
    assert (diag == x).all()

    def points(col: np.ndarray) -> list[tuple[float, float]]:
        return [(float(a), float(b)) for a, b in zip(x, col, strict=True) if np.isfinite(b)]

    drawn = sorted(p for g in groups for p in points(g))
    assert drawn == sorted(pairs)  # every pair once, in its place
    assert set(points(groups[-1])) == {(1.0, 1.2), (2.0, 2.05)}  # the last two pairs given
    assert len(return_map_data([(2.0, 2.0)] * 5000)[0]) == MAX_DRAWN + 2  # the latest only
    x0, *rest = return_map_data([])
    assert len(x0) == 2 and all(np.isnan(c).all() for c in rest[1:])
    long = "behind: 0.62x of 1x (machine cannot keep up); " + "x" * 200
    box = status_html(long)
    assert "white-space:normal" in box and long in box  # wrapped, nothing cut


def test_the_viewer_reads_the_results_folder_the_writers_fill(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from sim_core.cli.main import main
    from sim_core.contract import results
    from web import paths

    assert paths.DEFAULT_BIFURCATION == results.RESULTS_DIR / results.BIFURCATION_FILE
    with pytest.raises(ValueError):
        results.surface_atlas_file(results.RESULTS_DIR, "gravity", "constraint")
    monkeypatch.setenv(results.RESULTS_ENV, str(tmp_path))
    assert results.results_dir() == tmp_path
    # what `insect-gait atlas` writes is where the viewer looks for it (per axis and ground)
    args = ["atlas", "--axis", "mass", "--beta", "0.64", "--values", "3", "--d31", "1.9:2.3:0.4",
            "--no-refine", "--no-progress", "--backend", "local", "--workers", "1",
            "--out", str(tmp_path), "--cache", str(tmp_path / "cache")]  # fmt: skip
    assert main(args) == 0
    written = results.surface_atlas_file(tmp_path, "mass", "constraint")
    assert SurfaceAtlas.model_validate_json(written.read_text()).values == [3.0]
    assert math.isfinite(controls.RAMP_HOLD_S.initial)


SURFACE_JSON = Path(__file__).resolve().parents[2] / "docs" / "figures" / "surface.json"
BETAS = (0.55, 0.80)  # the viewer's beta slider, the panel's x axis


def _surface() -> DriftSurface:
    surface, note = load_validated(SURFACE_JSON, DriftSurface, "drift surface")
    assert surface is not None, note
    return surface


def _zeros(svg: str, kind: str, resolved: str = "(?:true|false)") -> int:
    return len(re.findall(f'<circle class="zero" data-kind="{kind}" data-resolved="{resolved}"',
                          svg))  # fmt: skip


def test_the_drift_surface_draws_its_zeros_bands_folds_and_first_pass_cells() -> None:
    surface = _surface()
    svg = surface_svg(surface, "", (0.66, 2.3), BETAS)
    assert 'data-plot="surface"' in svg and 'class="note"' not in svg
    stable = [z for z in surface.zeros if z.stable]
    unstable = [z for z in surface.zeros if not z.stable]
    assert stable and unstable  # the file has both kinds, so the counts below can fail
    assert _zeros(svg, "stable") == len(stable) and _zeros(svg, "unstable") == len(unstable)
    faint = sum(not z.resolved for z in surface.zeros)
    assert _zeros(svg, "(?:un)?stable", "false") == faint
    assert svg.count('opacity="0.4"') == faint  # unresolved zeros drawn fainter
    assert svg.count('class="near-zero"') == len(surface.near_zeros)
    assert svg.count('class="fold"') == len(surface.folds)
    # branches: solid lines between stable zeros, dashed between unstable ones
    assert re.search(r'class="link" data-kind="stable"(?![^>]*dasharray)', svg)
    assert re.search(r'class="link" data-kind="unstable"[^>]*stroke-dasharray', svg)
    # one cell per usable probe of the first pass; refinement probes lie off its grid
    grid = {round(d, 6) for d in surface.config.d31_grid}
    cells = [p for p in surface.points
             if p.usable and p.drift is not None and round(p.pin_d31, 6) in grid]  # fmt: skip
    assert len(cells) < sum(p.usable for p in surface.points)
    assert f'data-n-cells="{len(cells)}"' in svg
    assert "drift per cycle, mrad" in svg


def test_the_drift_colour_scale_is_symmetric_red_where_delta31_grows() -> None:
    assert drift_level(0.009) == pytest.approx(1.0)  # 9 mrad: log10(1 + 9)
    assert drift_level(-0.009) == pytest.approx(-1.0)
    assert drift_colour(0.0, 2.0) == "#ffffff"
    assert drift_colour(2.0, 2.0) == "#b2182b" and drift_colour(5.0, 2.0) == "#b2182b"
    assert drift_colour(-2.0, 2.0) == "#2166ac"
    half_up, half_down = drift_colour(1.0, 2.0), drift_colour(-1.0, 2.0)
    assert int(half_up[1:3], 16) > int(half_up[5:7], 16)  # reddish
    assert int(half_down[5:7], 16) > int(half_down[1:3], 16)  # bluish


def _live(svg: str) -> tuple[float, float, str]:
    m = re.search(r'<circle class="live" data-inside="(\w+)" cx="([\d.]+)" cy="([\d.]+)"', svg)
    assert m, svg[-800:]
    return float(m[2]), float(m[3]), m[1]


def test_the_live_point_rings_at_its_beta_and_delta31() -> None:
    surface = _surface()
    # viewBox 300 wide, plot from x 34 to 286: beta 0.65 on 0.55-0.80 is 0.4 of the way
    x, y, inside = _live(surface_svg(surface, "", (0.65, 2.0), BETAS))
    assert x == pytest.approx(34 + 0.4 * 252, abs=0.06) and inside == "true"
    # plot from y 16 (Delta31 3.5) to 130 (1.3): 2.0 is 0.7 / 2.2 of the way up
    assert y == pytest.approx(130 - 0.7 / 2.2 * 114, abs=0.06)
    x2, _, _ = _live(surface_svg(surface, "", (0.70, 2.0), BETAS))
    assert x2 - x == pytest.approx(0.2 * 252, abs=0.1)
    # outside the surface's Delta31 range: at the edge, and said so
    _, y_top, inside = _live(surface_svg(surface, "", (0.65, 4.5), BETAS))
    assert y_top == pytest.approx(16) and inside == "false"
    assert 'class="live"' not in surface_svg(surface, "", (0.65, None), BETAS)


@pytest.mark.parametrize(
    ("content", "says"),
    [(None, "no drift surface: "), ("{}", "surface.json is not a DriftSurface: config")],
)
def test_without_a_surface_file_the_panel_says_why(
    tmp_path: Path, content: str | None, says: str
) -> None:
    path = tmp_path / "surface.json"
    if content is not None:
        path.write_text(content)
    surface, note = WatchedFile(path, DriftSurface, "drift surface").get()
    assert surface is None and says in note
    svg = surface_svg(surface, note, (0.66, 2.0), BETAS)
    assert 'data-plot="surface"' in svg and 'class="note"' in svg
    assert html.escape(says) in svg and 'class="zero"' not in svg and 'class="live"' not in svg


def test_the_viewer_looks_for_the_surface_where_reproduce_writes_it() -> None:
    from sim_core.contract import SURFACE_FILE
    from web import paths

    assert paths.DEFAULT_SURFACE == paths.DEFAULT_BIFURCATION.parent / SURFACE_FILE

"""The numerics report: the table, the figures and the JSON come from one grid, and a saved grid
redraws without simulating."""

from __future__ import annotations

from pathlib import Path

import pytest

from sim_core.cli.main import main
from sim_core.numerics.convergence import GridPoint
from sim_core.numerics.report import grid_markdown, load_grid, save_grid, update_numerics_doc

OK = GridPoint("implicitfast", 5e-5, 0.5, 0.03, True, None, "", 6.0, 0.01, (2.05, 1.7), 0.0006)
FAILED = GridPoint("rk4", 1e-3, 0.001, None, False, "flip")
INFO: dict[str, object] = {"reference_wall_per_sim_s": 2.5, "reference_drift_error": 0.0024}


def test_table_gives_the_speed_up_only_where_a_configuration_runs() -> None:
    table = grid_markdown([OK, FAILED], INFO)
    ok_row = next(line for line in table.splitlines() if line.startswith("| implicitfast"))
    bad_row = next(line for line in table.splitlines() if line.startswith("| rk4"))
    assert "**ok**" in ok_row and "5.0x" in ok_row and "0.0006" in ok_row and "1.0%" in ok_row
    assert "fails" in bad_row and "flip" in bad_row and "x |" not in bad_row
    assert "0.0024" in table  # the paper's own drift error is stated


def test_saved_grid_round_trips(tmp_path: Path) -> None:
    path = tmp_path / "numerics.json"
    save_grid(path, [OK, FAILED], INFO)
    points, info = load_grid(path)
    assert points == [OK, FAILED] and info == INFO


def test_from_json_redraws_figures_and_the_doc_section(tmp_path: Path) -> None:
    grid = tmp_path / "numerics.json"
    save_grid(grid, [OK, FAILED], INFO)
    doc = tmp_path / "NUMERICS.md"
    doc.write_text("intro\n<!-- numerics:begin -->\nold\n<!-- numerics:end -->\nrest\n")
    out = tmp_path / "figs"
    assert main(["numerics", "--from-json", str(grid), "--out", str(out), "--doc", str(doc)]) == 0
    text = doc.read_text()
    assert "old" not in text and "| implicitfast | 5e-05 | **ok**" in text
    assert text.startswith("intro\n") and text.endswith("rest\n")
    assert text == update_numerics_doc(text, [OK, FAILED], INFO)
    for name in ("numerics_pareto.png", "numerics_map.png"):
        assert (out / name).stat().st_size > 0


def test_from_json_with_a_bad_file_is_a_usage_error(tmp_path: Path, capsys) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text("{}")
    assert main(["numerics", "--from-json", str(bad), "--out", str(tmp_path), "--no-doc"]) == 2
    assert "error" in capsys.readouterr().err


def test_a_doc_without_the_section_is_refused() -> None:
    with pytest.raises(ValueError, match="numerics:begin"):
        update_numerics_doc("no markers", [OK], INFO)


def test_quick_grid_end_to_end(tmp_path: Path) -> None:
    """`insect-gait numerics --quick` as a user runs it (~1 minute on 2 cores): figures and
    data written, a known-failing configuration reported as failed with its kind, the default
    one running, and no document touched."""
    doc = Path(__file__).resolve().parents[2] / "docs" / "NUMERICS.md"
    before = doc.read_text()
    assert main(["numerics", "--quick", "--out", str(tmp_path)]) == 0
    points, info = load_grid(tmp_path / "numerics.json")
    cell = {(p.label, p.dt_s): p for p in points}
    bad = cell[("implicitfast", 1e-3)]
    assert bad.status == "fails" and bad.failure and bad.error_rad is None
    good = cell[("implicitfast", 5e-5)]
    assert good.status != "fails" and good.error_rad is not None
    assert good.drift_error is not None and good.drift_error < 0.01
    assert isinstance(info["reference_wall_per_sim_s"], float)
    for name in ("numerics_pareto.png", "numerics_map.png"):
        assert (tmp_path / name).stat().st_size > 0
    assert doc.read_text() == before

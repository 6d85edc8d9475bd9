"""Issue 53, points 1-2 at the command line: every command that simulates takes the run's
options as flags generated from RunSpec (bar what it varies itself), so a new field reaches
each with no other file edited; `surface` and `atlas` take model parameters as `run` does,
record them, and name an atlas of other parameters apart from the defaults' file."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import pytest
from pydantic import Field

import sim_core.cli.runflags
from sim_core.cli.atlas import atlas_path
from sim_core.cli.fields import flag
from sim_core.cli.main import build_parser, main
from sim_core.cli.numerics import CONVERGE_VARIES
from sim_core.cli.paper import FINDER_VARIES
from sim_core.cli.runflags import output_tag, provenance_fields, tagged
from sim_core.cli.surface import SURFACE_VARIES
from sim_core.contract import (
    BIFURCATION_FILE,
    DriftSurface,
    ModelChoice,
    RunSpec,
    SurfaceAtlas,
    surface_atlas_file,
)

FIGURES = Path(__file__).resolve().parents[2] / "docs" / "figures"
# each command that simulates, and what it sets per run itself (its own constants: a command
# that stopped varying a field and forgot to give it back as a flag fails here)
VARIES: dict[str, tuple[str, ...]] = {
    "run": (),
    "return-map": ("d31_init",),
    "converge": CONVERGE_VARIES,
    "surface": SURFACE_VARIES,
    "surface-check": SURFACE_VARIES,
    "atlas": SURFACE_VARIES,
    "finder": FINDER_VARIES,
}
# the least each command needs to parse
ARGV: dict[str, list[str]] = {
    "run": ["--beta", "0.62"],
    "return-map": ["--beta", "0.62"],
    "converge": [],
    "surface": ["--beta", "0.62"],
    "surface-check": [],
    "atlas": ["--axis", "mass"],
    "finder": [],
}
# one tiny drift surface: two probes, 3 simulated s
TINY = ["--beta", "0.655", "--d31", "1.9:2.3:0.4", "--no-refine", "--no-progress",
        "--backend", "inline"]  # fmt: skip


def _commands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _run_fields(command: str, extra: list[str] | None = None) -> dict[str, Any]:
    args = build_parser().parse_args([command, *ARGV[command], *(extra or [])])
    return dict(sim_core.cli.runflags.run_fields(args))


@pytest.mark.parametrize("command", sorted(VARIES))
def test_each_command_takes_every_runspec_field_but_what_it_varies(command: str) -> None:
    help_text = " ".join(_commands(build_parser())[command].format_help().split())
    args = build_parser().parse_args([command, *ARGV[command]])
    wanted = [n for n in RunSpec.model_fields if n not in VARIES[command]]
    assert args.run_fields == wanted
    for name in wanted:
        words = " ".join((RunSpec.model_fields[name].description or "").split())[:30]
        assert f"{flag(name)} " in help_text and words in help_text, (command, name)


def test_a_new_runspec_field_is_a_flag_of_every_command(monkeypatch: pytest.MonkeyPatch) -> None:
    """A field added to the spec (a toy subclass standing in for an edited RunSpec) is a
    flag of each command with its words, and reaches the fields the command hands the core."""

    class Grown(RunSpec):
        swing_scale: float = Field(1.0, gt=0.0, le=2.0, description="swing height scale (0, 2]")

    monkeypatch.setattr(sim_core.cli.runflags, "RunSpec", Grown)
    commands = _commands(build_parser())
    for command in VARIES:
        text = " ".join(commands[command].format_help().split())
        assert "--swing-scale SWING_SCALE swing height scale (0, 2] (default: 1)" in text, command
        assert _run_fields(command, ["--swing-scale", "1.5"])["swing_scale"] == 1.5, command


class _Seen(Exception):
    """Raised by the spy once it has seen the first run a command hands the core."""


def _spy(monkeypatch: pytest.MonkeyPatch, module: Any, name: str, seen: list[Any]) -> None:
    """Replace `module.name` (a function that takes the runs' specs) by one that records
    what it was given and stops the command there (nothing is simulated)."""

    def record(*args: Any, **kwargs: Any) -> Any:
        seen.append(args[:2])  # (the spec or specs, the model's parameters)
        raise _Seen

    monkeypatch.setattr(module, name, record)


def _specs(given: Any) -> list[RunSpec]:
    if isinstance(given, RunSpec):
        return [given]
    return [s for s in given if isinstance(s, RunSpec)]


@pytest.mark.parametrize("command", sorted(VARIES))
def test_a_run_field_given_reaches_the_runs_of_every_command(
    command: str, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """--phi1-init (a field none of these but `run` took before) and a model parameter reach
    the specs and parameters the command hands the core."""
    import sim_core.model.runner
    import sim_core.numerics.convergence
    import sim_core.paper.protocols
    import sim_core.paper.search
    import sim_core.paper.surface

    seen: list[Any] = []
    where = {
        "run": (sim_core.model.runner, "simulate"),
        "return-map": (sim_core.paper.protocols, "simulate_batch"),
        "converge": (sim_core.numerics.convergence, "simulate_batch"),
        "surface": (sim_core.paper.surface, "run_task"),
        "surface-check": (sim_core.paper.surface, "run_task"),
        "atlas": (sim_core.paper.surface, "run_task"),
        "finder": (sim_core.paper.search, "run_task"),
    }
    _spy(monkeypatch, *where[command], seen)
    files = {
        "surface-check": ["--finder", str(FIGURES / BIFURCATION_FILE)],
        "atlas": ["--out", str(tmp_path)],
        "finder": ["--out", str(tmp_path), "--beta", "0.62"],
    }.get(command, [])
    backend = ["--cache", str(tmp_path / "cache"), "--backend", "inline", "--no-progress"]
    runs_here = command in ("surface", "surface-check", "atlas", "finder")
    argv = [command, *ARGV[command], *files, *(backend if runs_here else []),
            "--phi1-init", "0.25", "--param", "kp_lift=0.001"]  # fmt: skip
    with pytest.raises(_Seen):
        main(argv)
    given, params = seen[0]
    specs = _specs(given)
    assert specs and all(s.phi1_init == 0.25 for s in specs), (command, given)
    assert params.leaf("kp_lift") == 0.001, command


def test_a_surface_with_a_model_parameter_records_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "s.json"
    argv = ["surface", *TINY, "--cache", str(tmp_path / "cache"), "--out", str(out),
            "--setting", "soft_legs", "--param", "kp_lift=0.001"]  # fmt: skip
    assert main(argv) == 0
    surface = DriftSurface.model_validate_json(out.read_text())
    choice = ModelChoice(setting="soft_legs", params={"kp_lift": 0.001})
    assert surface.setting == "soft_legs" and surface.params == choice.changed()
    assert surface.params["kp_lift"] == 0.001  # on top of the setting's own kp_lift
    assert f"model: {choice.words()}" in capsys.readouterr().out


def test_an_atlas_of_other_parameters_is_written_apart_from_the_defaults(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    default = surface_atlas_file(tmp_path, "slope", "constraint")
    default.write_text("the defaults' atlas, which the viewer reads")
    argv = ["atlas", "--axis", "slope", "--values", "0", *TINY, "--no-walks",
            "--cache", str(tmp_path / "cache"), "--out", str(tmp_path),
            "--param", "kp_lift=0.001"]  # fmt: skip
    assert main(argv) == 0
    assert default.read_text() == "the defaults' atlas, which the viewer reads"
    written = [p for p in tmp_path.glob("surface_atlas_slope_constraint-*.json")]
    assert len(written) == 1 and written[0].with_suffix(".png").is_file()
    atlas = SurfaceAtlas.model_validate_json(written[0].read_text())
    assert atlas.params == {"kp_lift": 0.001} and atlas.setting is None
    assert str(written[0]) in capsys.readouterr().out


@pytest.mark.parametrize("command", ["surface", "atlas"])
def test_an_unknown_model_parameter_is_refused_by_name(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = [command, *ARGV[command], "--cache", str(tmp_path / "cache"), "--out",
            str(tmp_path / ("s.json" if command == "surface" else "")),
            "--param", "kp_lfit=0.001"]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"insect-gait {command}: error: --param: ")
    assert "unknown model parameter 'kp_lfit'" in err and "kp_lift" in err  # the hint
    assert list(tmp_path.iterdir()) in ([], [tmp_path / "cache"])  # nothing computed


def test_the_defaults_keep_their_file_names_and_others_get_their_own() -> None:
    folder = Path("docs/figures")
    plain = ModelChoice()
    assert output_tag({}, plain) == ""
    assert atlas_path(folder, "mass", plain, {}) == folder / "surface_atlas_mass_constraint.json"
    penalty = ModelChoice(ground="penalty")  # the ground names the file already
    assert atlas_path(folder, "slope", penalty, {}) == folder / "surface_atlas_slope_penalty.json"
    # a default value typed out is the defaults: the same numbers, the same file
    assert output_tag({"body_mass_g": 3.0, "phase_reset": True}, plain) == ""
    default_gain = ModelChoice().model_params().leaf("kp_lift")
    assert output_tag({}, ModelChoice(params={"kp_lift": default_gain})) == ""
    # a named setting alone is named; anything on top adds a hash of what differs
    soft = ModelChoice(setting="soft_legs")
    assert output_tag({}, soft) == "-soft_legs"
    tags = {
        output_tag({}, ModelChoice(params={"kp_lift": 0.001})),
        output_tag({}, ModelChoice(params={"kp_lift": 0.002})),
        output_tag({}, ModelChoice(setting="soft_legs", params={"kp_lift": 0.001})),
        output_tag({"dt_s": 2.5e-5}, plain),
        output_tag({"slope_deg": 5.0}, plain),
    }
    assert len(tags) == 5 and all(len(t.split("-")[-1]) == 8 for t in tags), tags
    assert output_tag({}, ModelChoice(params={"kp_lift": 0.001})) == output_tag(
        {}, ModelChoice(params={"kp_lift": 0.001})
    )
    assert tagged(folder / BIFURCATION_FILE, "-soft_legs").name == "bifurcation-soft_legs.json"


def test_a_finder_file_of_other_parameters_records_them_in_its_config() -> None:
    assert provenance_fields({}, ModelChoice()) == {}  # the defaults' file as it was
    record = provenance_fields(
        {"dt_s": 2.5e-5, "body_mass_g": 3.0}, ModelChoice(ground="penalty", setting="soft_legs")
    )
    assert record["ground"] == "penalty" and record["setting"] == "soft_legs"
    assert record["params"] == ModelChoice(setting="soft_legs").changed()
    assert record["run"] == {"dt_s": 2.5e-5}  # 3 g is the default: not recorded
    # what the viewer reads of a finder's ground (web/conditions.py: config's "ground")
    assert json.loads(json.dumps(record))["ground"] == "penalty"

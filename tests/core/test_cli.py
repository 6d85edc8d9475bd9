"""The command line: one-line errors with exit code 2, and the documented JSON."""

import json
import subprocess
import sys
from typing import Any

import pytest

from lab.cli import main as lab_main
from sim_core.cli.main import build_parser, main

BAD = [
    ["--beta", "0.5"],
    ["--beta", "1.0"],
    ["--beta", "0.6", "--body-mass-g", "0"],
    ["--beta", "0.6", "--slope-deg", "90"],
    ["--beta", "0.6", "--slope-deg", "-95"],
    ["--beta", "0.6", "--dt-s", "0"],
    ["--beta", "0.6", "--duration-s", "-1"],
    ["--beta", "abc"],
    ["--beta", "0.6", "--integrator", "verlet"],
    [],
]


@pytest.mark.parametrize("args", BAD)
def test_bad_arguments_exit_2_with_one_line(args: list[str], capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        code = main(["run", *args])
        raise SystemExit(code)
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "error" in err
    assert "Traceback" not in err


def test_run_json_has_the_documented_keys() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "sim_core.cli", "run", "--beta", "0.62", "--duration-s", "0.5",
         "--json"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    obj = json.loads(out.stdout)
    keys = {"beta", "d31", "d31_final", "gait", "speed_cm_s", "duty_factor_measured", "diverged"}
    assert keys <= obj.keys() and "error" in obj
    assert obj["diverged"] is False and obj["error"] is None
    assert all(0 <= x < 6.2832 for x in obj["d31"])


@pytest.mark.parametrize(
    "args",
    [
        ["readings", "--params", "[1]"],
        ["readings", "--params", "{bad json"],
        ["readings", "--stop-if-settled-s", "50"],
        ["readings", "--robust", "--finder"],
        ["slope-heading", "--params", "[1]"],
    ],
)
def test_study_overrides_are_checked_before_anything_runs(args: list[str], capsys) -> None:
    """--params must be ModelParams overrides (one helper checks both commands), and a
    screen's settled stop must lie inside its runs."""
    assert lab_main(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"python -m lab {args[0]}: error:") and "Traceback" not in err


def test_the_first_run_names_its_gait_without_any_other_flag() -> None:
    """Issue 42's first command: no --duration-s means until settled (30 s, else on to 60)."""
    out = subprocess.run(
        [sys.executable, "-m", "sim_core.cli", "run", "--beta", "0.62", "--d31-init", "3.0"],
        capture_output=True, text=True, check=True,
    ).stdout  # fmt: skip
    assert "ran 30 s (stopped settled)" in out and "gait tripod" in out
    assert "final Delta31 2.95" in out and ": settled" in out


def test_run_takes_the_ground() -> None:
    args = ["--beta", "0.62", "--duration-s", "0.5", "--ground", "penalty", "--json"]
    out = subprocess.run([sys.executable, "-m", "sim_core.cli", "run", *args],
                         capture_output=True, text=True, check=True)  # fmt: skip
    assert json.loads(out.stdout)["error"] is None
    bad = subprocess.run([sys.executable, "-m", "sim_core.cli", "run", "--beta", "0.62",
                          "--ground", "ice"], capture_output=True, text=True)  # fmt: skip
    assert bad.returncode == 2 and "invalid choice: 'ice'" in bad.stderr


def test_a_fall_is_told_in_the_insects_words_and_a_blow_up_as_numerics(capsys) -> None:
    assert main(["run", "--beta", "0.66", "--slope-deg", "60", "--duration-s", "0.6"]) == 1
    out = capsys.readouterr().out
    assert "the insect slid backwards at t = 0.25 s" in out and "will not help" in out
    assert "DIVERGED" not in out and "diverged" not in out


def test_the_products_help_lists_the_users_commands_and_the_lab_keeps_the_studies() -> None:
    from lab.cli import build_parser as lab_parser

    product = build_parser().format_help()
    lab = lab_parser().format_help()
    studies = ("calibrate", "sensitivity", "diagnose", "slope-heading", "timing-lines",
               "readings", "finder-check", "finder-claims", "finder-atlas")  # fmt: skip
    for name in ("run", "reproduce", "surface", "atlas", "finder", "api", "viewer"):
        assert f"    {name} " in product, name
    for name in studies:
        assert f"    {name} " not in product and f"    {name} " in lab, name
    assert "issue 3" not in product and "python -m lab --help" in product


def test_run_help_lists_every_runspec_field_with_its_default_from_the_model() -> None:
    import argparse

    from pydantic import BaseModel, Field

    from sim_core.cli.fields import add_field_flags, flag
    from sim_core.contract import RunSpec

    parser: Any = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    text = " ".join(sub.choices["run"].format_help().split())
    for name, info in RunSpec.model_fields.items():
        assert f"{flag(name)} " in text, name
        assert " ".join((info.description or "").split())[:40] in text, name
    assert "(default: 2 pi/3 = 2.094)" in text and "--no-phase-reset" in text

    # a new field is a new flag with its words and default, and only given flags reach it
    class Toy(BaseModel):
        gain_per_s: float = Field(12.5, gt=0, description="a gain, 1/s (0, inf)")
        on: bool = True

    p = argparse.ArgumentParser()
    names = add_field_flags(p, Toy)
    assert "a gain, 1/s (0, inf) (default: 12.5)" in " ".join(p.format_help().split())
    assert vars(p.parse_args([])) == {} and names == ["gain_per_s", "on"]
    assert vars(p.parse_args(["--gain-per-s", "3", "--no-on"])) == {"gain_per_s": 3.0, "on": False}

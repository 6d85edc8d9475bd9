"""The edges a new user hit (issue 23): the CLI and the API apply one rule with one wording,
a NaN is called a NaN, and a coarse run says that its numbers are coarse."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from pydantic import ValidationError

from server.kinds.run import RunJob
from sim_core import RunSpec
from sim_core.cli.common import TRACEBACK_ENV
from sim_core.cli.main import main
from sim_core.contract import MAX_STABLE_DT_S, step_problem
from sim_core.model.gait import DUTY_TOLERANCE, run_warnings


def _cli_error(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    code = main(["run", *args])
    return code, capsys.readouterr().err.strip()


def _api_error(**fields: object) -> str:
    with pytest.raises(ValidationError) as exc:
        RunJob.model_validate(fields)
    return "; ".join(e["msg"] for e in exc.value.errors())


@pytest.mark.parametrize(
    ("args", "fields"),
    [
        (["--integrator", "euler"], {"integrator": "euler"}),  # the default step, too coarse
        (["--integrator", "rk4", "--dt-s", "5e-5"], {"integrator": "rk4", "dt_s": 5e-5}),
        (["--dt-s", "1e-3"], {"dt_s": 1e-3}),
    ],
)
def test_cli_and_api_refuse_an_unstable_step_in_the_same_words(
    args: list[str], fields: dict[str, object], capsys: pytest.CaptureFixture[str]
) -> None:
    code, err = _cli_error(["--beta", "0.62", "--duration-s", "0.1", *args], capsys)
    assert code == 2 and err.count("\n") == 0
    api = _api_error(beta=0.62, duration_s=0.1, **fields)
    words = api.removeprefix("Value error, ")
    assert "cannot be stable with integrator" in words
    assert err.endswith(words), (err, words)  # the CLI adds only "insect-gait run: --dt-s:"


def test_the_rule_is_the_measured_limit() -> None:
    for name, limit in MAX_STABLE_DT_S.items():
        assert step_problem(name, limit) is None
        assert step_problem(name, limit * 1.01) is not None


@pytest.mark.parametrize("flag", ["--duration-s", "--beta", "--d31-init", "--dt-s"])
def test_a_nan_is_called_a_nan(flag: str, capsys: pytest.CaptureFixture[str]) -> None:
    args = ["--beta", "0.62", flag, "nan"] if flag != "--beta" else ["--beta", "nan"]
    code, err = _cli_error(args, capsys)
    assert code == 2
    assert "finite number" in err and "less than" not in err, err


def test_a_coarse_run_says_so() -> None:
    """discrete at 1e-3 s walks but steps its legs off beta: the result carries the warning
    (measured 0.635 for a commanded 0.66 over 3 s) instead of passing as a sound number."""
    from sim_core import RunSpec, simulate

    r = simulate(RunSpec(beta=0.66, duration_s=3.0, integrator="discrete", dt_s=1e-3))
    assert r.measures.duty_factor_measured is not None
    assert abs(r.measures.duty_factor_measured - 0.66) > DUTY_TOLERANCE
    text = " ".join(r.summary()["warnings"])
    assert "measured duty factor" in text and "coarser than the converged default" in text


def test_a_sound_run_has_no_warnings() -> None:
    from sim_core import RunSpec, simulate

    assert simulate(RunSpec(beta=0.62, duration_s=1.5)).measures.warnings == ()


def test_landing_share_above_one_is_explained() -> None:
    late = run_warnings(beta=0.66, duty_factor=0.66, landing=1.154, integrator="implicitfast",
                        dt_s=5e-5, converged_dt_s=5e-5)  # fmt: skip
    assert len(late) == 1 and "late" in late[0] and "1 = at the AEP" in late[0]
    early = run_warnings(beta=0.66, duty_factor=0.66, landing=0.7, integrator="implicitfast",
                         dt_s=5e-5, converged_dt_s=5e-5)  # fmt: skip
    assert "early" in early[0]
    assert not run_warnings(beta=0.66, duty_factor=0.655, landing=1.02, integrator="rk4",
                            dt_s=2e-5, converged_dt_s=5e-5)  # fmt: skip
    assert math.isfinite(DUTY_TOLERANCE)


def test_a_vanishing_step_is_refused_not_a_crash(capsys: pytest.CaptureFixture[str]) -> None:
    """dt_s 5e-324 made the substep count overflow (a 500 found by the API fuzz test)."""
    words = _api_error(dt_s=5e-324, control_dt_s=5e-324, duration_s=1.0)
    assert "too small" in words
    code, err = _cli_error(["--beta", "0.62", "--dt-s", "5e-324"], capsys)
    assert code == 2 and "too small" in err and err.count("\n") == 0


# ---- issue 30: one contract for the CLI and the API (cost bounds, d31_init, body mass) ------


@pytest.mark.parametrize(
    ("args", "fields", "needle"),
    [
        # a vanishing step: was a MemoryError (67 GiB) in the worker and a 17-line traceback
        (["--dt-s", "1e-12"], {"dt_s": 1e-12}, "the smallest step a run may take is 1e-06 s"),
        # 6e8 physics steps: was accepted and held the only worker for hours
        (["--duration-s", "600", "--dt-s", "1e-6", "--control-dt-s", "5e-4"],
         {"duration_s": 600, "dt_s": 1e-6, "control_dt_s": 5e-4}, "at most 6e+07"),
    ],
)  # fmt: skip
def test_cli_and_api_refuse_an_unbounded_cost_in_the_same_words(
    args: list[str], fields: dict[str, object], needle: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code, err = _cli_error(["--beta", "0.62", *args], capsys)
    assert code == 2 and err.count("\n") == 0 and "Traceback" not in err
    api = _api_error(**{"beta": 0.62, **fields}).removeprefix("Value error, ")
    assert needle in api
    assert err.endswith(api), (err, api)


@pytest.mark.parametrize(
    ("flag", "value", "field", "needle"),
    [
        ("--d31-init", "9", "d31_init", "6.283185"),  # was wrapped silently to 2.717
        ("--d31-init", "-0.5", "d31_init", "0"),
        ("--body-mass-g", "0.1", "body_mass_g", "less than its six legs"),  # ran before
    ],
)
def test_cli_and_api_share_the_ranges(
    flag: str, value: str, field: str, needle: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code, err = _cli_error(["--beta", "0.62", flag, value], capsys)
    assert code == 2 and err.count("\n") == 0 and needle in err, err
    number = float(value)
    with pytest.raises(ValidationError):
        RunJob.model_validate({field: [number] if field == "d31_init" else number})
    with pytest.raises(ValidationError):
        RunSpec(**{field: number})


def test_return_map_help_names_each_option_and_its_default(
    capsys: pytest.CaptureFixture[str],
) -> None:
    with pytest.raises(SystemExit):
        main(["return-map", "--help"])
    out = capsys.readouterr().out
    for text in ("duty factor", "(default: 16)", "(default: 3.0)", "JSON object"):
        assert text in out, out


def test_return_map_names_only_the_broken_rule(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["return-map", "--beta", "0.62", "--n-init", "0"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--n-init" in err and "--beta" not in err and "--duration-s" not in err, err
    assert main(["return-map", "--beta", "1.2"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--beta" in err and "--n-init" not in err, err


# ---- issue 55: every bad input is one line on stderr, never a traceback ---------------------


def _bad_inputs(tmp: Path) -> dict[str, list[str]]:
    """Bad inputs across the commands, each refused before anything is computed (the files
    they name: `_write_files`)."""
    plain, bad_json, a_file = tmp / "plain.md", tmp / "bad.json", tmp / "a-file"
    cache = ["--cache", str(tmp / "cache")]
    return {
        "params, missing file": ["params", "--update-doc", str(tmp / "missing.md")],
        "params, no markers": ["params", "--update-doc", str(plain)],
        "params, a folder": ["params", "--update-doc", str(tmp)],
        "surface, --out in a missing folder": [
            "surface", "--beta", "0.62", "--out", str(tmp / "no" / "s.json"), *cache],
        "surface, --cache on a file": ["surface", "--beta", "0.62", "--cache", str(a_file)],
        "surface, beta out of range": ["surface", "--beta", "0.3", *cache],
        "surface-check, not the finder's file": ["surface-check", "--finder", str(bad_json)],
        "atlas, --out on a file": ["atlas", "--axis", "mass", "--out", str(a_file), *cache],
        "bench, nan seconds": ["bench", "--sim-seconds", "nan"],
        "converge, negative tolerance": ["converge", "--tolerance", "-1"],
        "converge, infinite duration": ["converge", "--duration-s", "inf"],
        "converge, a step past the bound": ["converge", "--dt-s", "1"],
        "numerics, not a grid file": [
            "numerics", "--from-json", str(bad_json), "--no-doc", "--out", str(tmp / "n")],
        "reproduce, a doc without markers": ["reproduce", "--doc", str(plain), *cache],
        "finder, --out on a file": ["finder", "--beta", "0.62", "--out", str(a_file), *cache],
        "return-map, nan beta": ["return-map", "--beta", "nan"],
        "run, not a number": ["run", "--beta", "abc"],
    }  # fmt: skip


def _write_files(tmp: Path) -> None:
    (tmp / "plain.md").write_text("# a document without the generated section's markers\n")
    (tmp / "bad.json").write_text("{}")
    (tmp / "a-file").write_text("")


def _one_line_error(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """(exit code, stderr) of `insect-gait ARGV` run in-process (argparse exits by
    SystemExit; any other exception fails the test as the traceback it would print)."""
    try:
        code = main(argv)
    except SystemExit as exc:
        code = int(exc.code or 0)
    return code, capsys.readouterr().err


@pytest.mark.parametrize("case", sorted(_bad_inputs(Path("/nonexistent"))))
def test_a_bad_input_is_one_line_without_a_traceback(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _write_files(tmp_path)
    argv = _bad_inputs(tmp_path)[case]
    code, err = _one_line_error(argv, capsys)
    assert code != 0, (case, err)
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"insect-gait {argv[0]}: error: "), err


def test_the_words_say_what_to_do(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _write_files(tmp_path)
    bad = _bad_inputs(tmp_path)
    _, err = _one_line_error(bad["params, no markers"], capsys)
    assert "<!-- params:begin -->" in err and "put those two lines" in err, err
    _, err = _one_line_error(bad["surface, --out in a missing folder"], capsys)
    assert "create it first" in err, err
    _, err = _one_line_error(bad["bench, nan seconds"], capsys)
    assert err.startswith("insect-gait bench: error: --sim-seconds: ") and "finite" in err, err
    _, err = _one_line_error(bad["surface-check, not the finder's file"], capsys)
    assert "`insect-gait finder` writes it" in err, err


def test_a_default_doc_outside_the_project_says_where_to_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    code, err = _one_line_error(["numerics", "--from-json", "x.json"], capsys)
    assert code == 2 and err.count("\n") == 1, err
    assert "docs/NUMERICS.md (the default --doc) is not here" in err and "--no-doc" in err, err
    assert not (tmp_path / "docs").exists()


def test_params_update_doc_rewrites_a_file_with_markers(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    doc = tmp_path / "model.md"
    doc.write_text("before\n<!-- params:begin -->\nSTALE TABLE\n<!-- params:end -->\nafter\n")
    assert main(["params", "--update-doc", str(doc)]) == 0
    text = doc.read_text()
    assert "STALE TABLE" not in text and "| parameter |" in text and text.endswith("after\n")
    assert str(doc) in capsys.readouterr().out


def test_an_error_from_inside_a_command_is_one_line_unless_a_traceback_is_asked(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The net under every command: a file error from deep inside (a full disk) prints one
    line and exits 1; INSECT_GAIT_TRACEBACK=1 lets it raise for a developer."""
    import sim_core.docsections

    def full_disk(*_: object) -> str:
        raise OSError(28, "No space left on device", "docs/MODEL.md")

    monkeypatch.setattr(sim_core.docsections, "parameter_markdown", full_disk)
    code, err = _one_line_error(["params"], capsys)
    assert code == 1
    assert err == "insect-gait params: error: docs/MODEL.md: No space left on device\n"
    monkeypatch.setenv(TRACEBACK_ENV, "1")
    with pytest.raises(OSError, match="No space left"):
        main(["params"])


def test_the_surface_command_labels_its_progress_and_says_where_it_caches(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Two probes (about 3 simulated s): the bar says "surface", the cache is named once."""
    cache = tmp_path / "cache"
    argv = ["surface", "--beta", "0.655", "--d31", "1.9:2.3:0.4", "--no-refine",
            "--backend", "inline", "--cache", str(cache)]  # fmt: skip
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert "surface:" in err and "reproduce" not in err, err
    assert err.count(f"cached in {cache}") == 1, err
    assert out.startswith("beta 0.655: stable ") and "S " not in out, out
    assert out.count("falls through zero") == 1  # the words it used, explained once


def test_describe_words_every_kind_of_zero_and_band() -> None:
    """No "S/U", no "|d| >= 0.00 mrad": each zero in words, a band's smallest drift with its
    significant digits, and a legend of only the words used."""
    from sim_core.cli.surface import describe
    from sim_core.contract.surface import DriftSurface, NearZero, SurfaceZero

    zeros = [
        SurfaceZero(beta=0.62, d31=1.77, lo=1.75, hi=1.8, stable=True, slope=-0.1, resolved=True),
        SurfaceZero(beta=0.62, d31=2.9, lo=2.88, hi=2.95, stable=False, slope=0.1,
                    resolved=False),
    ]  # fmt: skip
    band = NearZero(beta=0.62, lo=2.6, hi=2.8, sign=-1, min_abs_drift=4.5e-6)
    surface = DriftSurface(config={"floor_rad": 3e-4}, betas=[0.62], points=[], zeros=zeros,
                           near_zeros=[band], branches=[], folds=[], sim_s=10.0,
                           body_mass_g=3.0, slope_deg=0.0, ground="constraint")  # fmt: skip
    text = describe(surface)
    first = text.splitlines()[0]
    assert first.startswith("beta 0.62: stable 1.770, unstable 2.900 (unresolved, 2.88-2.95)")
    assert "near-zero band 2.60-2.80 (drift -, smallest 0.0045 mrad per cycle)" in first
    assert "0.00 mrad" not in text and "|d|" not in text
    for word in ("stable X:", "unstable X:", "unresolved (LO-HI):", "near-zero band LO-HI:"):
        assert sum(line.startswith(word) for line in text.splitlines()) == 1, word
    assert "0.3 mrad per cycle" in text

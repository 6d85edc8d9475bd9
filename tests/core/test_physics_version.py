"""The result cache's key: the physics' version, not its sources' bytes (sim_core.model.version).

The promise behind it (a change that moves a number bumps the version) is checked against a
committed dump of every way a number is made (`physics_golden`)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from sim_core.model.params import ModelParams
from sim_core.model.spec import RunSpec
from sim_core.model.version import PHYSICS_VERSION
from sim_core.runs.tasks import params_json, run_task, spec_json
from tests.core.physics_golden import GOLDEN_FILE, differences, dump

ROOT = Path(__file__).resolve().parents[2]


def test_the_physics_numbers_are_those_of_the_version() -> None:
    golden = json.loads(GOLDEN_FILE.read_text())
    diffs = differences(golden["dump"], json.loads(json.dumps(dump())))
    if golden["version"] == PHYSICS_VERSION:
        assert not diffs, (
            "simulated numbers moved without a new PHYSICS_VERSION (sim_core/model/version.py): "
            "bump it and regenerate with `python -m tests.core.physics_golden --write "
            f"--version NEW` ({len(diffs)} differences, first: {diffs[:5]})"
        )
    else:
        raise AssertionError(
            f"PHYSICS_VERSION is {PHYSICS_VERSION!r} but the committed numbers belong to "
            f"{golden['version']!r}: regenerate them with `--write --version {PHYSICS_VERSION}`"
        )


def test_the_golden_comparison_can_fail() -> None:
    golden = json.loads(GOLDEN_FILE.read_text())["dump"]
    moved = json.loads(json.dumps(golden))
    moved["constraint"]["d31"][-1] += 1e-6
    assert differences(golden, moved) == [
        "/constraint/d31[5]: "
        + (f"{golden['constraint']['d31'][-1]!r} != {moved['constraint']['d31'][-1]!r}")
    ]


def test_defaults_are_left_out_of_the_key() -> None:
    # so that a new field whose default keeps the physics keeps every cached run's key
    assert params_json(None) == params_json(ModelParams()) == "{}"
    assert spec_json(RunSpec()) == "{}"
    assert json.loads(params_json(ModelParams.of(ground="penalty"))) == {"ground": "penalty"}
    t = run_task(RunSpec(beta=0.62, duration_s=2.0))
    assert t.run_spec() == RunSpec(beta=0.62, duration_s=2.0) and t.duration_s == 2.0


def test_a_comment_in_the_physics_sources_keeps_the_cache_keys(tmp_path: Path) -> None:
    copy = tmp_path / "sim_core"
    shutil.copytree(ROOT / "sim_core", copy, ignore=shutil.ignore_patterns("__pycache__"))
    for f in [*copy.joinpath("model").glob("*.py"), copy / "runs" / "tasks.py"]:
        f.write_text(f.read_text() + "\n# a comment changes no number\n")
    code = (
        "from sim_core.model.params import ModelParams\n"
        "from sim_core.model.spec import RunSpec\n"
        "from sim_core.runs.tasks import run_task\n"
        "import sim_core; print(sim_core.__file__)\n"
        "print(run_task(RunSpec(beta=0.62), ModelParams.of(ground='penalty')).key)\n"
    )
    env = os.environ | {"PYTHONPATH": str(tmp_path), "INSECT_GAIT_KERNEL_CACHE": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, check=True,
                         capture_output=True, text=True).stdout.split()  # fmt: skip
    assert out[0].startswith(str(copy))  # the edited copy was the one imported
    assert out[1] == run_task(RunSpec(beta=0.62), ModelParams.of(ground="penalty")).key


def test_the_key_names_each_parameter_by_its_leaf_so_regrouping_keeps_it() -> None:
    from pydantic import BaseModel

    from sim_core.model.params import leaf_values

    class Flat(BaseModel):
        friction: float = 1.0
        dt: float = 5e-5
        ground: str = "constraint"

    class Contact(BaseModel):
        friction: float = 1.0
        ground: str = "constraint"

    class Grouped(BaseModel):
        contact: Contact = Contact()
        dt: float = 5e-5

    flat = Flat(friction=0.8, ground="penalty")
    grouped = Grouped(contact=Contact(friction=0.8, ground="penalty"))
    assert leaf_values(flat) == leaf_values(grouped) == {"friction": 0.8, "ground": "penalty"}
    assert leaf_values(Grouped()) == {}

    class Clash(BaseModel):
        contact: Contact = Contact()
        friction: float = 1.0

    with pytest.raises(ValueError, match="friction"):
        leaf_values(Clash(contact=Contact(friction=0.5), friction=0.5))
    # today's model: the key part and its reading back
    p = ModelParams.of(ground="penalty", friction=0.8)
    t = run_task(RunSpec(beta=0.62), p)
    assert json.loads(t.params) == {"friction": 0.8, "ground": "penalty"}
    assert t.model_params() == p

"""Model parameters at the edges (issue 53, item 2): `insect-gait run --param`, a REST run
job's `params` and `simulate(spec, ModelParams.of(...))` give the same Delta31 series; the job
records the parameters it ran with (result provenance, CSV); default parameters keep every task
key, a leaf changes it; a named setting is one value. Real server, real worker, real runs."""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Callable

import pytest
from api_harness import Server, result_of, submit, wait_status

import sim_core
from server.kinds import JOB_SPEC_ADAPTER
from server.kinds.bounds import tidy
from server.kinds.run import RunJob
from sim_core.cli import main
from sim_core.contract import ModelChoice, ModelParams
from sim_core.research import named_params

LEAF = {"kp_lift": 1.0e-3}  # a non-default joint gain (default 3.3e-3): a different walk
JOB = {"kind": "run", "beta": 0.66, "duration_s": 0.6, "d31_init": [2.0], "params": LEAF}


def _direct() -> list[float]:
    spec = sim_core.RunSpec(beta=0.66, d31_init=2.0, duration_s=0.6)
    return [float(x) for x in sim_core.simulate(spec, ModelParams.of(**LEAF)).events.d31]


def test_cli_rest_and_python_give_the_same_delta31(
    make_server: Callable[..., Server], capsys: pytest.CaptureFixture[str]
) -> None:
    direct = _direct()
    default = sim_core.simulate(sim_core.RunSpec(beta=0.66, d31_init=2.0, duration_s=0.6))
    assert direct != [float(x) for x in default.events.d31]  # the leaf reaches the physics

    argv = ["run", "--beta", "0.66", "--d31-init", "2.0", "--duration-s", "0.6", "--json"]
    assert main([*argv, "--param", "kp_lift=1e-3"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert cli["d31"] == direct
    assert cli["model"]["changed"] == LEAF

    srv = make_server()
    with srv.client() as c:
        job = submit(c, JOB)
        assert job["spec"]["params"] == LEAF
        done = wait_status(c, job["id"], {"done", "failed"}, timeout=120)
        assert done["status"] == "done", done["error"]
        result = result_of(c, job["id"])["result"]
        # the service stores 12 significant digits (`server.kinds.bounds.tidy`)
        assert result["runs"][0]["d31"] == [tidy(x) for x in direct]
        assert result["provenance"]["params"] == LEAF
        assert result["provenance"]["params_hash"] == sim_core.contract.params_hash(
            ModelParams.of(**LEAF)
        )
        r = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv"})
        (row,) = csv.DictReader(io.StringIO(r.text))
        assert json.loads(row["params"]) == LEAF


@pytest.mark.parametrize(
    ("flags", "words"),
    [
        (["--param", "kp_lifts=1e-3"], "--param: unknown model parameter 'kp_lifts'"),
        (["--param", "com_offset_x=0.1"], "--param: com_offset_x: Input should be less than"),
        (["--param", "dt=1e-5"], "use the field dt_s"),
        (["--param", "kp_lift"], "write NAME=VALUE"),
        (["--setting", "stiff"], "--setting: no model setting 'stiff'; known: soft_legs"),
        (["--param", "ground_stiffness=10"], "of the penalty ground only"),
    ],
)
def test_cli_refuses_a_bad_parameter_in_one_line(
    flags: list[str], words: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", "--beta", "0.66", "--duration-s", "0.1", *flags]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err, err


def test_default_parameters_keep_the_task_keys_and_a_leaf_changes_them() -> None:
    """Before issue 53 a job's parameters were `ModelParams.of(ground=job.ground)`: a job
    without params keeps those keys on either ground; one with a leaf gets new ones."""
    spec = sim_core.RunSpec(beta=0.66, d31_init=2.0, duration_s=0.6)
    for ground in ("constraint", "penalty"):
        plain = JOB_SPEC_ADAPTER.validate_python({**JOB, "params": {}, "ground": ground})
        assert isinstance(plain, RunJob)
        old = sim_core.run_task(spec, ModelParams.of(ground=ground)).key
        assert sim_core.run_task(spec, plain.model_params()).key == old
        leafy = JOB_SPEC_ADAPTER.validate_python({**JOB, "ground": ground})
        assert isinstance(leafy, RunJob)
        assert sim_core.run_task(spec, leafy.model_params()).key != old


def test_a_named_setting_is_one_value_with_leaves_on_top() -> None:
    job = JOB_SPEC_ADAPTER.validate_python({**JOB, "params": {}, "setting": "soft_legs"})
    assert job.model_params() == named_params("soft_legs")
    both = JOB_SPEC_ADAPTER.validate_python({**JOB, "setting": "soft_legs"})
    assert both.model_params() == named_params("soft_legs", **LEAF)
    assert both.changed()["kp_lift"] == LEAF["kp_lift"]
    assert both.words().startswith("soft_legs (")


def test_every_kind_passes_its_parameters_to_the_core() -> None:
    """Every kind builds its runs' parameters from `Physics.model_params`, which is the
    choice's: a leaf given to any kind is in the parameters it hands the core."""
    from server.kinds import KINDS

    for kind in KINDS.values():
        assert kind.model.model_params is ModelChoice.model_params, kind.name

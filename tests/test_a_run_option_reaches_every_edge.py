"""Issue 53's acceptance: a field added to `RunSpec` reaches every edge with no other file
edited: `insect-gait run`'s flags, every REST job's schema in /openapi.json, a job's echoed spec
and its result, the runs of the surface, atlas and bifurcation jobs (the drift surface's
probes, the atlas's probes and walks, the finder's runs: each composed from the job's run
template), and the viewer's job body and settings export (and that file read back).

The field is added in a fresh interpreter (tests/new_run_option.py: a subclass of the real
RunSpec takes its place before anything else imports it, as a field declared in
sim_core/model/spec.py would), which reports what each edge shows of it and of a name nobody
added. An edge that lists its fields by hand instead of deriving them shows nothing and fails
here.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    folder = tmp_path_factory.mktemp("new-option")
    env = os.environ | {"PYTHONPATH": str(REPO), "PYTHONWARNINGS": "ignore"}
    done = subprocess.run(
        [sys.executable, "-m", "tests.new_run_option", str(folder)],
        cwd=REPO, env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    out: dict[str, Any] = json.loads(done.stdout.strip().splitlines()[-1])
    return out


def _shown(report: dict[str, Any], path: str) -> Any:
    """The edge's finding at `path` ("cli.flag"), or the failure that cut it short."""
    node = report
    for key in path.split("."):
        if key not in node:  # the edge broke before it got there: its `error` says why
            return node
        node = node[key]
    return node


@pytest.mark.parametrize(
    ("edge", "expected"),
    [
        ("cli.flag", "value"),  # `insect-gait run --swing-scale 1.5`
        ("cli.spec", "value"),  # the spec `run` simulates
        *[(f"openapi.{kind}", "default") for kind in ("run", "return_map", "sweep",
                                                       "hysteresis", "bifurcation", "surface",
                                                       "atlas")],
        ("echoed_spec", "value"),  # POST /v1/jobs: the job's spec as stored and shown
        ("result", "value"),  # a run job's result: the spec each run ran
        ("instruments.surface", "every run's"),  # every probe of a surface job
        ("instruments.atlas", "every run's"),  # every probe (and walk) of an atlas job
        ("instruments.bifurcation", "every run's"),  # every run of the finder
        ("viewer.submit_body", "value"),  # the run job the viewer's panel offers
        ("viewer.export", "value"),  # the viewer's settings file
        ("viewer.loaded", "value"),  # that file read back: the spec the walk restarts at
    ],
)  # fmt: skip
def test_a_new_run_option_reaches_the_edge(
    report: dict[str, Any], edge: str, expected: str
) -> None:
    """`expected`: the value the job or command set, the option's default (a schema), or the
    value set on every run an instrument asked for."""
    shown = _shown(report, edge)
    want = {"value": report["value"], "default": report["default"],
            "every run's": [report["value"]]}[expected]  # fmt: skip
    assert report["value"] != report["default"]
    assert shown["new"] == want, shown
    assert shown["absent"] in (None, [None]), shown  # the check reads the fields themselves


def test_every_kind_is_looked_at(report: dict[str, Any]) -> None:
    from server.kinds import NAMES

    assert set(report["openapi"]) == set(NAMES)
    assert all(r.get("runs", 0) >= 2 for r in report["instruments"].values()), report


def test_the_new_option_is_refused_out_of_range_by_name(report: dict[str, Any]) -> None:
    """Its bounds are RunSpec's, stated in the 422 as the API states every range."""
    assert report["refused"] == [422, [["swing_scale", "0 < swing_scale <= 2"]]]

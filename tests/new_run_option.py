"""A run option added to `RunSpec`, looked for at every edge: run in a fresh interpreter by
tests/test_a_run_option_reaches_every_edge.py as `python -m tests.new_run_option FOLDER`.

The option (`NAME`, default `DEFAULT`, bounds (0, 2]) is added to the real RunSpec before anything
but its own module has imported it, as a field declared in sim_core/model/spec.py would be: a
subclass with one more field takes the class's place in its module, and every module imported
afterwards (the contract, the CLI, the server, the viewer) reads that one. Nothing else is
edited: each edge shows the option only if it derives its fields from RunSpec.

Prints one JSON object: for each edge, what it shows of `NAME` (the value given, or its
default where the edge states one) and of `ABSENT`, a name nobody added (None everywhere, or
the check would be looking at something other than the fields).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from pydantic import Field, create_model

import sim_core.model.spec as spec_module

NAME = "swing_scale"
VALUE = 1.5
DEFAULT = 1.0
ABSENT = "stance_scale"


def add_option() -> None:
    """RunSpec with `NAME` in its module, before any other module has imported it."""
    old = spec_module.RunSpec
    assert NAME not in old.model_fields and ABSENT not in old.model_fields
    holders = [m for m, mod in list(sys.modules.items())
               if mod is not spec_module and vars(mod).get("RunSpec") is old]  # fmt: skip
    assert not holders, f"imported RunSpec before the option was added: {holders}"
    field = Field(DEFAULT, gt=0.0, le=2.0, description="a test's new run option, (0, 2]")
    spec_module.RunSpec = create_model(  # type: ignore[misc]
        "RunSpec", __base__=old, __module__=spec_module.__name__, **{NAME: (float, field)}
    )


def _both(found: dict[str, Any]) -> dict[str, Any]:
    """What an edge shows of the new option and of the name nobody added."""
    return {"new": found.get(NAME), "absent": found.get(ABSENT)}


def _edge(look: Callable[[], dict[str, Any]]) -> dict[str, Any]:
    """What `look` finds, or, where the edge refuses or breaks on the option, nothing and why
    (so that each edge fails on its own)."""
    try:
        return look()
    except Exception as exc:  # the edge's own failure is the finding
        return {"new": None, "absent": None, "error": f"{type(exc).__name__}: {exc}"[:2000]}


def cli() -> dict[str, Any]:
    """`run`'s flags: in its help, and a spec from a command line that sets the option."""
    from sim_core.cli.main import build_parser
    from sim_core.cli.walk import _spec_from_args

    parser = build_parser()
    args = parser.parse_args(["run", "--beta", "0.66", f"--{NAME.replace('_', '-')}", "1.5"])
    spec = _spec_from_args(args)
    return {"flag": _both(vars(args)), "spec": _both(spec.model_dump())}


def rest(folder: Path) -> dict[str, Any]:
    """The REST API in-process (no workers): every kind's request schema in /openapi.json,
    a job's echoed spec, a 422 naming the option out of its range, and a run job's result
    (executed here, its records holding the spec each run ran)."""
    from fastapi.testclient import TestClient

    from server.app import create_app
    from server.kinds import JOB_SPEC_ADAPTER, KINDS, ComputeSettings, execute, open_compute
    from server.settings import Settings

    settings = Settings(db_path=folder / "jobs.sqlite3", cache_dir=folder / "cache", workers=0)
    body = {"kind": "run", "beta": 0.66, "duration_s": 0.05, "d31_init": [2.0], NAME: VALUE}
    with TestClient(create_app(settings)) as client:
        schemas = client.get("/openapi.json").json()["components"]["schemas"]
        posted = client.post("/v1/jobs", json=body)
        refused = client.post("/v1/jobs", json=body | {NAME: 3.0})
    props = {k: schemas[kind.model.__name__]["properties"] for k, kind in KINDS.items()}

    def result() -> dict[str, Any]:
        job = JOB_SPEC_ADAPTER.validate_python(body | {"include_series": True})
        where = ComputeSettings(cache_dir=folder / "run")
        return _both(execute(job, open_compute(where, lambda _: None, 1))["runs"][0]["spec"])

    return {
        "openapi": {k: _both({n: p[n]["default"] for n in (NAME, ABSENT) if n in p})
                    for k, p in props.items()},
        "echoed_spec": _both(posted.json().get("spec") or {}) | {"status": posted.status_code},
        "refused": [refused.status_code, [(e["field"], e["allowed"])
                                          for e in refused.json()["detail"]]],
        "result": _edge(result),
    }  # fmt: skip


def instruments(folder: Path) -> dict[str, Any]:
    """A surface, an atlas and a bifurcation job run by their kinds' runners, every run they
    ask for recorded (the toy gait of tests/core/synthetic_gait.py answers): the option's
    values over all their runs' specs."""
    import sim_core
    from server.kinds import JOB_SPEC_ADAPTER, Compute, execute
    from tests.core.synthetic_gait import fake_execute

    held = {"d31_lo": 1.9, "d31_hi": 2.3, "d31_step": 0.4, "refine": False}
    jobs = {
        "surface": {"kind": "surface", "beta_range": {"start": 0.64, "stop": 0.655, "steps": 2},
                    **held},
        "atlas": {"kind": "atlas", "axis": "mass", "betas": [0.64], "values": [3.0, 5.0],
                  "walks": True, **held},
        "bifurcation": {"kind": "bifurcation", "beta_range": {"start": 0.62, "stop": 0.66,
                        "steps": 2}, "starts": 2, "duration_s": 2.0, "max_borders": 0,
                        "kick_rad": 0.0, "neighbour_seeds": False},
    }  # fmt: skip

    def runs_of(kind: str) -> dict[str, Any]:
        seen: list[Any] = []

        def record(tasks: Any) -> list[dict[str, Any]]:
            seen.extend(tasks)
            return fake_execute(tasks)

        class Recording(Compute):
            def core(self, moving: Any) -> dict[str, Any]:
                return super().core(moving) | {"executor": record}

        cache = sim_core.ResultCache(folder / f"{kind}-cache")
        execute(JOB_SPEC_ADAPTER.validate_python(jobs[kind] | {NAME: VALUE}),
                Recording(lambda _: None, cache, sim_core.get_backend("inline")))  # fmt: skip
        values = {n: sorted({getattr(t.run_spec(), n, None) for t in seen}, key=str)
                  for n in (NAME, ABSENT)}  # fmt: skip
        return {"runs": len(seen), "new": values[NAME], "absent": values[ABSENT]}

    return {kind: _edge(lambda kind=kind: runs_of(kind)) for kind in jobs}


def viewer() -> dict[str, Any]:
    """The viewer walking a spec that sets the option: the job body its panel offers to
    submit, its settings export, and that file read back (the spec a loaded file walks)."""
    from web.export import run_job, settings_json
    from web.settings_file import JobInputs, load_settings
    from web.state import ViewerState

    state = ViewerState.of(spec_module.RunSpec.model_validate({"beta": 0.66, NAME: VALUE}))
    settings = state.settings(JobInputs(ramp=None, duration_s=1.0, api_url="http://x"))
    file = settings_json(settings, made=state.provenance())
    loaded = load_settings(file).spec().model_dump()
    return {"submit_body": _both(run_job(settings)), "export": _both(json.loads(file)),
            "loaded": _both(loaded)}  # fmt: skip


def main(folder: Path) -> None:
    add_option()
    report = {"value": VALUE, "default": DEFAULT, "cli": _edge(cli), **rest(folder),
              "instruments": instruments(folder), "viewer": _edge(viewer)}  # fmt: skip
    print(json.dumps(report))


if __name__ == "__main__":
    main(Path(sys.argv[1]))

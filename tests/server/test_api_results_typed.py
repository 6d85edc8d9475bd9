"""Every kind's result is typed to the leaf and served validated, keys and values unchanged.

One job of every kind in the registry runs in this process (the real runners, real
simulations, a tiny size each), its stored form goes into a real SQLite store as a done job,
and a real server (no workers) serves it: the JSON a client gets equals the stored JSON (every
key, every float bit for bit) and validates against the kind's result model. A result stored
before a measure existed, or in a shape that no longer fits, is still served. And no result
model anywhere down its tree holds a `dict[str, Any]` (or any untyped value).
"""

from __future__ import annotations

import dataclasses
import types
import typing
from collections.abc import Iterator
from typing import Any

import pytest
from api_harness import Server, free_port
from pydantic import BaseModel

from server.jobs import JobStore
from server.kinds import (
    JOB_SPEC_ADAPTER,
    KIND_RESULTS,
    KINDS,
    NAMES,
    ComputeSettings,
    execute,
    open_compute,
)

SHORT = {"beta": 0.66, "duration_s": 0.4}
HELD = {"d31_lo": 1.9, "d31_hi": 2.3, "d31_step": 0.4, "refine": False}
# one small job per kind (every name in the registry: the test below checks it)
JOBS: dict[str, dict[str, Any]] = {
    "run": {"kind": "run", **SHORT, "d31_init": [1.0, 3.0]},
    "run_series": {"kind": "run", **SHORT, "d31_init": [2.0], "include_series": True},
    "return_map": {"kind": "return_map", **SHORT, "d31_init": [1.0, 3.0], "lag": 1},
    "sweep": {"kind": "sweep", "beta_range": {"start": 0.62, "stop": 0.70, "steps": 2},
              "d31_init": [2.0], "duration_s": 0.4},
    "hysteresis": {"kind": "hysteresis", "ramp": {"param": "beta", "start": 0.70, "turn": 0.64,
                   "hold_s": 0.1, "ramp_s": 0.3}},
    "bifurcation": {"kind": "bifurcation", "beta_range": {"start": 0.62, "stop": 0.66,
                    "steps": 2}, "starts": 2, "duration_s": 2.0, "max_borders": 0,
                    "kick_rad": 0.0, "neighbour_seeds": False},
    "surface": {"kind": "surface", "beta_range": {"start": 0.64, "stop": 0.655, "steps": 2},
                **HELD},
    "atlas": {"kind": "atlas", "axis": "mass", "betas": [0.64], "values": [3.0], "walks": False,
              **HELD},
}  # fmt: skip


def test_every_kind_in_the_registry_has_a_job_here() -> None:
    assert {spec["kind"] for spec in JOBS.values()} == set(NAMES)


def _done(store: JobStore, kind: str, spec: dict[str, Any], result: dict[str, Any]) -> str:
    """Store `result` as a done job of `kind`, through the store's own queue and claim."""
    row = store.submit(kind, spec, 1.0, 1000)
    claim = store.claim_next()
    assert claim is not None and claim.job_id == getattr(row, "id", None)
    assert store.finish_done(claim, result)
    return claim.job_id


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Server, dict[str, Any]]]:
    """name -> (job id, stored result), every job run here and served by a real server."""
    tmp = tmp_path_factory.mktemp("typed")
    store = JobStore(tmp / "jobs.sqlite3")
    store.init()
    where = ComputeSettings(cache_dir=tmp / "cache")
    out: dict[str, Any] = {}
    for name, spec in JOBS.items():
        job = JOB_SPEC_ADAPTER.validate_python(spec)
        result = execute(job, open_compute(where, lambda _: None, 1))
        out[name] = (_done(store, job.kind_name(), job.model_dump(mode="json"), result), result)
    srv = Server(db=tmp / "jobs.sqlite3", port=free_port(),
                 env={"INSECT_GAIT_WORKERS": "0", "INSECT_GAIT_LOG_LEVEL": "warning"},
                 log=tmp / "server.log")  # fmt: skip
    srv.start()
    yield srv, out
    srv.stop()


@pytest.mark.parametrize("name", sorted(JOBS))
def test_a_result_is_served_validated_with_its_stored_keys_and_values(
    served: tuple[Server, dict[str, Any]], name: str
) -> None:
    srv, jobs = served
    job_id, stored = jobs[name]
    with srv.client() as c:
        r = c.get(f"/v1/jobs/{job_id}/result")
    assert r.status_code == 200 and "x-result-schema" not in r.headers, r.text
    body = r.json()
    assert body["result"] == stored  # the same keys, the same floats (== on floats: exact)
    assert list(body["result"]) == list(stored)  # and in the same order
    kind = body["kind"]
    typed = KIND_RESULTS[kind].model_validate(body["result"])
    assert typed.model_dump(mode="json", exclude_unset=True) == stored
    assert len(typed.records) >= 1
    assert all(isinstance(row, KINDS[kind].row) for row in typed.records)


def test_a_result_stored_before_a_measure_existed_is_served_without_it(
    served: tuple[Server, dict[str, Any]],
) -> None:
    """Lenient reading: a measure added since the result was stored stays absent."""
    srv, jobs = served
    _, stored = jobs["run"]
    old = {**stored, "runs": [{k: v for k, v in run.items() if k != "retouches_per_stance"}
                              for run in stored["runs"]]}  # fmt: skip
    old["records"] = [{k: v for k, v in row.items() if k != "retouches_per_stance"}
                      for row in stored["records"]]  # fmt: skip
    job_id = _done(JobStore(srv.db), "run", JOBS["run"], old)
    with srv.client() as c:
        r = c.get(f"/v1/jobs/{job_id}/result")
    assert r.status_code == 200 and "x-result-schema" not in r.headers
    assert r.json()["result"] == old


def test_a_result_that_no_longer_fits_its_model_is_served_as_stored_and_said_so(
    served: tuple[Server, dict[str, Any]],
) -> None:
    srv, jobs = served
    _, stored = jobs["sweep"]
    old = {**stored, "records": [{**row, "a_renamed_measure": 1.5} for row in stored["records"]]}
    job_id = _done(JobStore(srv.db), "sweep", JOBS["sweep"], old)
    with srv.client() as c:
        r = c.get(f"/v1/jobs/{job_id}/result")
    assert r.status_code == 200 and r.headers["x-result-schema"] == "unvalidated"
    assert r.json()["result"] == old


def test_a_stored_job_in_the_flat_hysteresis_shape_still_validates() -> None:
    """A hysteresis job an older server stored (flat fields) is read as the same `Ramp`."""
    new = JOB_SPEC_ADAPTER.validate_python(JOBS["hysteresis"])
    flat = {"kind": "hysteresis", "parameter": "beta", "start": 0.70, "turn": 0.64,
            "hold_s": 0.1, "ramp_s": 0.3}  # fmt: skip
    assert JOB_SPEC_ADAPTER.validate_python(flat) == new
    assert new.model_dump(mode="json")["ramp"] == JOBS["hysteresis"]["ramp"]  # stored as `ramp`


def _untyped(tp: Any, seen: set[Any], path: str) -> list[str]:
    """Where, down the type `tp`, a value is left untyped (Any, a bare dict or list, or a dict
    of Any): the paths to it."""
    if tp is Any or tp is dict or tp is list or tp is object:
        return [path]
    origin = typing.get_origin(tp)
    args = typing.get_args(tp)
    if origin is typing.Annotated:
        return _untyped(args[0], seen, path)
    if origin in (typing.Union, types.UnionType, list, tuple, dict, typing.Literal) or args:
        if origin is typing.Literal:
            return []
        return [p for a in args if a is not Ellipsis for p in _untyped(a, seen, f"{path}[]")]
    if isinstance(tp, type) and tp not in seen:
        seen.add(tp)
        if issubclass(tp, BaseModel):
            return [p for n, f in tp.model_fields.items()
                    for p in _untyped(f.annotation, seen, f"{path}.{n}")]  # fmt: skip
        if dataclasses.is_dataclass(tp):
            hints = typing.get_type_hints(tp)
            return [p for f in dataclasses.fields(tp)
                    for p in _untyped(hints[f.name], seen, f"{path}.{f.name}")]  # fmt: skip
    return []


@pytest.mark.parametrize("name", NAMES)
def test_no_result_model_holds_an_untyped_value(name: str) -> None:
    """Down to the instruments' own protocols (`config`: the finder's, the surface's and the
    atlas's, typed to the core's config types)."""
    result = KIND_RESULTS[name]
    assert _untyped(result, set(), result.__name__) == []
    assert _untyped(dict[str, Any], set(), "x") == ["x[]"]  # the check itself can fail

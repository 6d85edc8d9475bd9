"""The REST `bifurcation` kind is the finder `insect-gait finder` runs: the same function
(`find`), so the same answer for the same settings."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from api_harness import Server, result_of, submit, wait_status

from sim_core import find
from sim_core.contract import Cell, CellResult, FinderConfig, FinderOutput
from sim_core.paper.search import task_runner
from sim_core.runs.backends import InlineBackend
from sim_core.runs.cache import ResultCache

TINY = {"starts": 2, "duration_s": 2.0}


def _same(a: list[CellResult], b: list[CellResult]) -> None:
    """Equal up to the API's 12 significant digits (`kinds._tidy`)."""
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        assert x.beta == y.beta and len(x.runs) == len(y.runs)
        assert all(abs(p.d31_init - q.d31_init) < 1e-9 for p, q in zip(x.runs, y.runs, strict=True))
        for p, q in zip(x.runs, y.runs, strict=True):
            assert p.settled == q.settled and p.attractor == q.attractor
            assert (p.final is None) == (q.final is None)
            if p.final is not None and q.final is not None:
                assert abs(p.final - q.final) < 1e-9
        assert [a.gait for a in x.attractors] == [a.gait for a in y.attractors]
        assert len(x.borders) == len(y.borders) and len(x.ghosts) == len(y.ghosts)


def _run(tmp_path: Path) -> Any:
    return task_runner(ResultCache(tmp_path / "cache"), InlineBackend(), None, progress=False)


def test_bifurcation_job_is_the_finder(make_server: Callable[..., Server], tmp_path: Path) -> None:
    extra = {"bisect_duration_s": 2.0, "border_tol_rad": 1.0, "max_borders": 1}
    spec = {"kind": "bifurcation", "beta_range": {"start": 0.62, "stop": 0.70, "steps": 2},
            **TINY, **extra}  # fmt: skip
    srv = make_server(workers=1)
    with srv.client() as c:
        job = wait_status(c, submit(c, spec)["id"], {"done", "failed"})
        assert job["status"] == "done", job["error"]
        result = result_of(c, job["id"])["result"]
        assert c.get(f"/v1/jobs/{job['id']}/figure.png").content[:4] == b"\x89PNG"
        assert c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv"}).status_code == 200
    got = FinderOutput.model_validate(result["finder"])
    cfg = FinderConfig(**TINY, **extra)  # type: ignore[arg-type]
    direct = find([Cell(0.62), Cell(0.70)], cfg, _run(tmp_path))
    _same(got.cells, direct)
    kinds = {r["kind"] for r in result["records"]}
    assert kinds <= {"stable", "unstable", "ghost", "not settled"} and kinds

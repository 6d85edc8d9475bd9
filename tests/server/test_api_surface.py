"""The REST `surface` and `atlas` kinds are the drift surface `insect-gait surface` and `atlas`
compute: the same functions (`drift_surface`, `surface_atlas`), so the same probes, zeros,
folds and regions for the same settings."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from api_harness import Server, result_of, submit, wait_status

from sim_core.contract import DriftSurface, SurfaceAtlas, SurfaceConfig, surface_grid
from sim_core.paper.surface import drift_surface
from sim_core.paper.surface_atlas import surface_atlas
from sim_core.paper.surface_walks import WalkConfig
from sim_core.runs.cache import ResultCache


def test_surface_job_is_the_surface_command(
    make_server: Callable[..., Server], tmp_path: Path
) -> None:
    spec = {
        "kind": "surface",
        "beta_range": {"start": 0.64, "stop": 0.655, "steps": 2},
        "d31_lo": 1.9,
        "d31_hi": 2.3,
        "d31_step": 0.4,
        "refine": False,
    }
    srv = make_server(workers=1)
    with srv.client() as c:
        job = wait_status(c, submit(c, spec)["id"], {"done", "failed"}, timeout=240)
        assert job["status"] == "done", job["error"]
        result = result_of(c, job["id"])["result"]
        assert c.get(f"/v1/jobs/{job['id']}/figure.png").content[:4] == b"\x89PNG"
        csv = c.get(f"/v1/jobs/{job['id']}/result", params={"format": "csv"})
        assert csv.status_code == 200 and csv.text.startswith("beta,kind,pin_d31")
    got = DriftSurface.model_validate(result["surface"])
    cfg = SurfaceConfig(d31_grid=surface_grid(1.9, 2.3, 0.4))
    direct = drift_surface(
        [0.64, 0.655], cache=ResultCache(tmp_path), config=cfg, refine=False, progress=False
    )
    assert len(got.points) == len(direct.points) == 4
    for a, b in zip(got.points, direct.points, strict=True):
        assert a.drift is not None and b.drift is not None
        assert abs(a.drift - b.drift) < 1e-9 and a.usable == b.usable
    assert [(z.beta, z.stable) for z in got.zeros] == [(z.beta, z.stable) for z in direct.zeros]
    assert all(abs(a.d31 - b.d31) < 1e-9 for a, b in zip(got.zeros, direct.zeros, strict=True))
    kinds = {r["kind"] for r in result["records"]}
    assert "probe" in kinds and "zero" in kinds


def test_atlas_job_is_the_atlas_command(make_server: Callable[..., Server], tmp_path: Path) -> None:
    spec = {"kind": "atlas", "axis": "slope", "betas": [0.64, 0.70], "values": [-10.0, 10.0],
            "d31_lo": 1.7, "d31_hi": 2.3, "d31_step": 0.3, "refine": False}  # fmt: skip
    srv = make_server(workers=1)
    with srv.client() as c:
        job = wait_status(c, submit(c, spec)["id"], {"done", "failed"}, timeout=240)
        assert job["status"] == "done", job["error"]
        result = result_of(c, job["id"])["result"]
        assert c.get(f"/v1/jobs/{job['id']}/figure.png").content[:4] == b"\x89PNG"
    got = SurfaceAtlas.model_validate(result["atlas"])
    cfg = SurfaceConfig(d31_grid=surface_grid(1.7, 2.3, 0.3))
    direct = surface_atlas("slope", [0.64, 0.70], [-10.0, 10.0], cache=ResultCache(tmp_path),
                           config=cfg, refine=False, walks=WalkConfig(),
                           progress=False)  # fmt: skip
    assert got.param == "slope_deg" and len(got.points) == len(direct.points) == 4
    for a, b in zip(got.points, direct.points, strict=True):
        assert (a.beta, a.value, a.region, a.gaits) == (b.beta, b.value, b.region, b.gaits)
        # walks on by default, as the command: each cell checked, its states' finders named
        assert a.checked and (a.provenance, a.undecided) == (b.provenance, b.undecided)
        assert all(abs(x - y) < 1e-9 for x, y in zip(a.stable, b.stable, strict=True))
    assert [r["region"] for r in result["records"]] == [p.region for p in direct.points]
    assert [r["found_by"] for r in result["records"]] == [
        " ".join(p.provenance) for p in direct.points
    ]

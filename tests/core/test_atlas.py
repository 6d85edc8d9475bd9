"""The gait atlas on its quick grid: on a real Dask LocalCluster, the same answer as the local
backend, resumed from the cache without simulating, and written as JSON + PNG."""

from pathlib import Path

from sim_core.contract.finder import AtlasOutput
from sim_core.paper.atlas import AtlasConfig, run_atlas, write_atlas
from sim_core.runs.backends import InlineBackend, RunStats, get_backend
from sim_core.runs.cache import ResultCache


def test_atlas_on_dask_equals_local_and_resumes(tmp_path: Path) -> None:
    cfg = AtlasConfig.quick("mass")
    dask = get_backend("dask", workers=2, processes=False)
    try:
        first = run_atlas(cfg, ResultCache(tmp_path / "a"), dask, progress=False)
    finally:
        dask.close()
    local = run_atlas(cfg, ResultCache(tmp_path / "b"), InlineBackend(), progress=False)
    assert first.regions == local.regions and len(first.cells) == 4
    assert [c.runs for c in first.cells] == [c.runs for c in local.cells]
    stats = RunStats()
    again = run_atlas(cfg, ResultCache(tmp_path / "a"), InlineBackend(), progress=False,
                      stats=stats)  # fmt: skip
    assert stats.computed == 0 and stats.cached > 0 and again == first
    js, png = write_atlas(first, tmp_path / "out")
    back = AtlasOutput.model_validate_json(js.read_text())
    assert back.model_dump_json() == first.model_dump_json() and png.stat().st_size > 0

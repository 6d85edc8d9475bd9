"""The finder against independent 40 s runs at beta 0.62, 0.655, 0.70 (issue 28, point 3):
every stable point it reports is reached from near it, and every attractor that 8 independent
runs reach is in its output. ~15 minutes on 2 cores: `pytest -m slow`."""

from __future__ import annotations

from pathlib import Path

import pytest

from sim_core.paper.fixedpoints import FinderConfig
from sim_core.paper.validation import report, validate
from sim_core.runs.backends import get_backend
from sim_core.runs.cache import ResultCache


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_every_reported_point_is_reached_and_every_reached_attractor_is_reported(
    tmp_path: Path,
) -> None:
    backend = get_backend("local")
    try:
        checks = validate((0.62, 0.655, 0.70), FinderConfig(), ResultCache(tmp_path), backend,
                          progress=False)  # fmt: skip
    finally:
        backend.close()
    table = "\n".join(report(checks))
    for c in checks:
        assert c.finder.attractors, table
        assert all(ok for _, _, ok in c.reached), table
        assert all(ok for _, end, ok in c.independent if end is not None), table

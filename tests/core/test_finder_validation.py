"""The finder against independent 40 s runs at beta 0.62, 0.655, 0.70 (issue 28, point 3):
every stable point it reports is reached from near it, and every attractor that 8 independent
runs reach is in its output. ~15 minutes on 2 cores: `pytest -m slow`."""

from __future__ import annotations

from pathlib import Path

import pytest

from lab.finder_check import report, validate
from sim_core.contract.finder import FinderConfig
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
        assert not c.missing(), table
        # every settled end the finder does not list was put to its kick test
        assert all(e in c.kicked for _, e, ok in c.independent if e is not None and not ok)


def test_an_unlisted_end_counts_as_missed_only_if_a_kick_comes_back_to_it() -> None:
    from lab.finder_check import BetaCheck
    from sim_core.contract.finder import CellResult

    empty = CellResult(beta=0.655, body_mass_g=3.0, slope_deg=0.0, attractors=[], borders=[],
                       ghosts=[], runs=[], sim_s=0.0)  # fmt: skip
    c = BetaCheck(0.655, empty, independent=[(0.4, 4.58, False), (1.2, 1.74, True),
                                              (2.0, None, False), (3.0, 2.10, False)])  # fmt: skip
    # 4.58: kicks slide off (one still drifting near it is not a return); 2.10: one returns
    c.kicked = {4.58: ((2.91, False), (4.59, False)), 2.10: ((None, False), (2.11, True))}
    assert c.missing() == [2.10] and not c.ok
    assert (
        "4.580 (not an attractor: kicks end 2.910 (still drifting) / 4.590 (still" in report([c])[2]
    )
    assert "2.100 (missing)" in report([c])[2]
    c.kicked[2.10] = ((1.74, True), (1.74, True))
    assert c.missing() == [] and c.ok

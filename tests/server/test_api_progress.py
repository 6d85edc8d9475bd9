"""Every kind's progress moves while it runs: the drift surface, the atlas and the finder used
to report only when a chunk of runs or a round ended, so a job of one chunk sat at 0.00 until
done. Run in this process with a recording callback (the worker's callback, unthrottled)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from server.kinds import JOB_SPEC_ADAPTER, ComputeSettings, execute, open_compute
from server.kinds.progress import CAP, ChunkProgress

SMALL_GRID = {"d31_lo": 2.0, "d31_hi": 2.4, "d31_step": 0.2, "refine": False}
JOBS = {
    # 2 betas x 3 held values: 6 probes, one chunk of the core's 8
    "surface": {"kind": "surface", "beta_range": {"start": 0.62, "stop": 0.66, "steps": 2},
                **SMALL_GRID},
    "atlas": {"kind": "atlas", "betas": [0.62], "values": [2.0, 5.0], **SMALL_GRID},
    # one round of 2 starts per beta, nothing after it
    "bifurcation": {"kind": "bifurcation", "beta_range": {"start": 0.62, "stop": 0.66,
                    "steps": 2}, "starts": 2, "duration_s": 2.0, "max_borders": 0,
                    "kick_rad": 0.0, "neighbour_seeds": False},
}  # fmt: skip


@pytest.mark.parametrize("kind", sorted(JOBS))
def test_progress_moves_inside_a_single_chunk(kind: str, tmp_path: Path) -> None:
    seen: list[float] = []
    compute = open_compute(ComputeSettings(cache_dir=tmp_path), seen.append, 1)
    result: dict[str, Any] = execute(JOB_SPEC_ADAPTER.validate_python(JOBS[kind]), compute)
    assert result["records"]
    assert seen == sorted(seen) and max(seen) <= CAP, seen  # never back, never 1 early
    early = [x for x in seen if 0 < x < 0.5]
    assert len(early) >= 5, f"{kind}: progress reported {seen}"


def test_chunk_progress_follows_the_cores_reports() -> None:
    """Between two reports of the core, a chunk moves by its runs at the share per run the
    last report showed; the core's reports are kept; nothing goes back."""
    shown: list[float] = []
    cp = ChunkProgress(shown.append, runs=10)
    assert cp.per_run == pytest.approx(0.1)
    cp._chunk = 4  # a chunk of 4 ran (the executor sets it)
    cp.on_progress(0.2)  # the core: 4 runs made 0.2 -> 0.05 per run (a refining pass follows)
    assert cp.per_run == pytest.approx(0.05) and shown == [0.2]
    cp.show(0.1)  # behind what was shown: not reported
    cp.show(2.0)  # beyond the end: capped
    assert shown == [0.2, CAP]

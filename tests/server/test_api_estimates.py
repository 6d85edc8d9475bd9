"""The time left of a running job (`eta_s`): sane from the first poll, measured from where the
job's progress starts to move, and a history no tiny job can skew."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from pathlib import Path

import pytest

from server import estimates
from server.jobs import JobRow, JobStore
from server.status import JobStatus

RUN = {"kind": "run"}


def test_a_tiny_slow_job_does_not_set_the_rate_of_a_long_one() -> None:
    """A 0.3 s job that took 5 s (the engine loading on a fresh worker) beside a 6 s job that
    took 2 s: the median of per-job rates said 16.7 wall s per simulated s, and a 6 s job
    would have been told 100 s; pooled, every simulated second weighs once."""
    history = [(5.0, 0.3, RUN), (2.0, 6.0, RUN)]
    rate = estimates.wall_per_sim_second(history)
    assert rate == pytest.approx(7.0 / 6.3)
    assert 6.0 * rate < 7.0  # the median of per-job rates: 6 x 16.7 = 100 s
    assert estimates.wall_per_sim_second(history[1:]) == pytest.approx(2.0 / 6.0)
    assert estimates.wall_per_sim_second([]) is None


def test_the_own_rate_starts_when_progress_moves() -> None:
    """3 s since start, of which 2.5 s before the first report; at 5.6 % the job's own rate
    is measured over the 0.5 s it has moved: 8.4 s left, not the 50 s that 3 s at 5.6 % say."""
    moving = estimates.remaining_s(
        elapsed_s=3.0, moving_s=0.5, progress=0.056, sim_seconds=15, wall_per_sim_s=None
    )
    assert moving == pytest.approx(0.5 * 0.944 / 0.056)
    from_start = estimates.remaining_s(
        elapsed_s=3.0, progress=0.056, sim_seconds=15, wall_per_sim_s=None
    )
    assert from_start == pytest.approx(3.0 * 0.944 / 0.056)  # an older row: no moving_since
    # below MIN_PROGRESS the history still decides: 15 s x 0.3 - 3 s
    assert estimates.remaining_s(
        elapsed_s=3.0, moving_s=0.1, progress=0.001, sim_seconds=15, wall_per_sim_s=0.3
    ) == pytest.approx(1.5)


def test_moving_since_is_the_first_progress_of_each_attempt(tmp_path: Path) -> None:
    store = JobStore(tmp_path / "j.sqlite3")
    store.init()
    job = store.submit("run", RUN, 1.0, 10)
    assert isinstance(job, JobRow)
    claim = store.claim_next()
    assert claim is not None
    store.set_progress(claim, 0.0)
    first = store.get(job.id)
    assert first is not None and first.moving_since is None  # 0 is not moving yet
    store.set_progress(claim, 0.01)
    moving = store.get(job.id)
    assert moving is not None and moving.moving_since is not None
    store.set_progress(claim, 0.5)
    later = store.get(job.id)
    assert later is not None and later.moving_since == moving.moving_since  # kept
    assert store.worker_died(claim, "killed") == "requeued"
    again = store.claim_next()
    assert again is not None
    fresh = store.get(job.id)
    assert fresh is not None and fresh.moving_since is None  # a new attempt starts over


def test_eta_of_a_row_uses_its_moving_since() -> None:
    now = datetime.now(UTC)

    def stamp(seconds_ago: float) -> str:
        return (now - timedelta(seconds=seconds_ago)).isoformat().replace("+00:00", "Z")

    job = JobRow(id="j", kind="run", spec=RUN, status=JobStatus.RUNNING, progress=0.25,
                 attempts=1, requeues=0, sim_seconds=10.0, created_at=stamp(12),
                 started_at=stamp(12), finished_at=None, error=None, note=None,
                 moving_since=stamp(2))  # fmt: skip
    assert estimates.eta_of(job, now, None) == pytest.approx(6.0, abs=0.1)  # 2 s per 25 %

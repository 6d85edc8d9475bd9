"""The job store's guarantees on a real SQLite file, and the API's ranges against the core's."""

from __future__ import annotations

import sqlite3
from pathlib import Path
from typing import Any

import annotated_types as at
import pytest

from server.jobs import JobStore, QueueFull
from server.schemas import D31, RunJob, SweepJob


@pytest.fixture
def store(tmp_path: Path) -> JobStore:
    s = JobStore(tmp_path / "jobs.sqlite3")
    s.init()
    return s


def _submit(store: JobStore, limit: int = 10) -> str:
    out = store.submit("run", {"kind": "run"}, 1.0, limit)
    assert not isinstance(out, QueueFull)
    return str(out["id"])


def test_wal_mode_and_fifo_claims(store: JobStore) -> None:
    with sqlite3.connect(store.path) as conn:
        assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    ids = [_submit(store) for _ in range(3)]
    claims = [store.claim_next() for _ in range(3)]
    assert [c.job_id for c in claims if c] == ids
    assert store.claim_next() is None


def test_cancelled_job_cannot_be_overwritten_by_its_worker(store: JobStore) -> None:
    job_id = _submit(store)
    claim = store.claim_next()
    assert claim is not None
    assert store.cancel(job_id)[0] == "running"
    assert not store.set_progress(claim, 0.5)
    assert not store.finish_done(claim, {"records": []})
    assert not store.finish_failed(claim, "late")
    job = store.get(job_id)
    assert job is not None and job["status"] == "cancelled" and store.result(job_id) is None


def test_stale_attempt_is_fenced_after_recovery(store: JobStore) -> None:
    job_id = _submit(store)
    old = store.claim_next()
    assert old is not None
    assert store.recover_interrupted(max_requeues=1) == ([job_id], [])
    new = store.claim_next()
    assert new is not None and new.attempt == old.attempt + 1
    assert not store.finish_done(old, {"stale": True})
    assert store.finish_done(new, {"fresh": True})
    assert store.result(job_id) == {"fresh": True}


def test_queue_limit_counts_only_queued(store: JobStore) -> None:
    _submit(store, limit=2)
    _submit(store, limit=2)
    assert isinstance(store.submit("run", {}, 1.0, 2), QueueFull)
    assert store.claim_next() is not None
    _submit(store, limit=2)


def _bounds(metadata: list[Any]) -> dict[str, float]:
    out: dict[str, float] = {}
    for m in metadata:
        for key in ("gt", "ge", "lt", "le"):
            if isinstance(m, (at.Gt, at.Ge, at.Lt, at.Le)) and hasattr(m, key):
                out[key] = float(getattr(m, key))
    return out


@pytest.mark.parametrize(
    "name", ["beta", "body_mass_g", "slope_deg", "duration_s", "dt_s", "control_dt_s", "d31_init"]
)
def test_ranges_match_the_core_runspec(name: str) -> None:
    """The API refuses at the door what the core would refuse later, no more and no less."""
    sim_core = pytest.importorskip("sim_core")
    core = _bounds(sim_core.RunSpec.model_fields[name].metadata)
    if name == "d31_init":
        mine = _bounds(list(D31.__metadata__[0].metadata))
    else:
        mine = _bounds(RunJob.model_fields[name].metadata)
    assert mine == core


def test_sweep_size_counts_grid_times_list() -> None:
    job = SweepJob(beta_range={"start": 0.6, "stop": 0.7, "steps": 5}, d31_init=[1.0, 2.0])
    assert job.run_count() == 10
    assert job.total_sim_seconds() == pytest.approx(10 * job.duration_s)
    assert job.beta_range.values()[0] == 0.6 and job.beta_range.values()[-1] == pytest.approx(0.7)

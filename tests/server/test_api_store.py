"""The job store's guarantees on a real SQLite file, and the API's ranges against the core's."""

from __future__ import annotations

import math
import sqlite3
from pathlib import Path
from typing import Any

import annotated_types as at
import pytest

from server import errors, estimates
from server.jobs import (
    SCHEMA_VERSION,
    IdempotencyKey,
    JobRow,
    JobStore,
    QueueFull,
    Replayed,
    Simulations,
)
from server.kinds import bounds, common
from server.kinds.bounds import D31
from server.kinds.run import RunJob
from server.kinds.sweep import SweepJob
from server.status import JobStatus
from sim_core.contract import RunFailure, RunSpec


@pytest.fixture
def store(tmp_path: Path) -> JobStore:
    s = JobStore(tmp_path / "jobs.sqlite3")
    s.init()
    return s


def _submit(store: JobStore, limit: int = 10) -> str:
    out = store.submit("run", {"kind": "run"}, 1.0, limit)
    assert not isinstance(out, QueueFull)
    return out.id


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
    assert job is not None and job.status == "cancelled" and store.result(job_id) is None


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


def test_a_job_loses_one_worker_and_runs_again_the_second_loss_fails_it(store: JobStore) -> None:
    job = _submit(store)
    first = store.claim_next()
    assert first is not None and first.job_id == job
    assert store.worker_died(first, "killed A") == "requeued"
    row = store.get(job)
    assert (
        row is not None
        and row.status is JobStatus.QUEUED
        and "attempt 1: killed A" in (row.note or "")
    )
    assert store.worker_died(first, "late") == "gone"  # the old claim is fenced
    second = store.claim_next()
    assert second is not None and second.attempt == 2
    assert store.worker_died(second, "killed B") == "failed"
    row = store.get(job)
    assert row is not None and row.status is JobStatus.FAILED
    assert "attempt 1: killed A" in (row.error or "") and "attempt 2: killed B" in (row.error or "")


def test_a_version_1_store_gains_the_worker_deaths_column(tmp_path: Path) -> None:
    path = tmp_path / "old.sqlite3"
    with sqlite3.connect(path) as conn:  # the version-1 table, one job in it
        conn.executescript(
            "CREATE TABLE jobs (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE,"
            " kind TEXT NOT NULL, spec TEXT NOT NULL, status TEXT NOT NULL, progress REAL NOT"
            " NULL DEFAULT 0, attempts INTEGER NOT NULL DEFAULT 0, requeues INTEGER NOT NULL"
            " DEFAULT 0, sim_seconds REAL NOT NULL, created_at TEXT NOT NULL, started_at TEXT,"
            " finished_at TEXT, error TEXT, note TEXT); PRAGMA user_version = 1;"
        )
        conn.execute("INSERT INTO jobs (id, kind, spec, status, sim_seconds, created_at) VALUES"
                     " ('j1', 'run', '{}', 'queued', 1.0, '2026-11-28T00:00:00Z')")  # fmt: skip
    s = JobStore(path)
    s.init()
    with sqlite3.connect(path) as conn:
        assert conn.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION
        assert conn.execute("SELECT worker_deaths FROM jobs WHERE id = 'j1'").fetchone()[0] == 0
    claim = s.claim_next()
    assert claim is not None and s.worker_died(claim, "killed") == "requeued"
    row = s.get("j1")
    assert row is not None and row.requeues == 1


def test_requeues_counts_every_requeue_after_a_crash_each_crash_kept_to_its_limit(
    store: JobStore,
) -> None:
    """`requeues` (what the API shows) counts the worker's death and the server's stop alike;
    `max_requeues` still limits server stops only, and a clean shutdown counts as neither."""
    job = _submit(store)
    first = store.claim_next()
    assert first is not None and store.worker_died(first, "killed") == "requeued"
    second = store.claim_next()
    assert second is not None and store.requeue_on_shutdown(second)  # a clean stop: not counted
    row = store.get(job)
    assert row is not None and row.requeues == 1
    assert store.claim_next() is not None
    # the server died while it ran: a restart re-queues it, its first against max_requeues = 1
    assert store.recover_interrupted(max_requeues=1) == ([job], [])
    row = store.get(job)
    assert row is not None and row.requeues == 2 and row.status is JobStatus.QUEUED
    assert store.claim_next() is not None
    assert store.recover_interrupted(max_requeues=1) == ([], [job])
    row = store.get(job)
    assert row is not None and row.requeues == 2 and "1 time(s)" not in (row.error or "")
    assert "2 time(s)" in (row.error or "")


def test_a_version_2_store_counts_its_past_requeues(tmp_path: Path) -> None:
    """Version 2 counted server restarts in `requeues` and a worker death in `worker_deaths`
    only: on open, `restarts` takes the old count and `requeues` adds the worker's re-queue."""
    path = tmp_path / "v2.sqlite3"
    with sqlite3.connect(path) as conn:
        conn.executescript(
            "CREATE TABLE jobs (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE,"
            " kind TEXT NOT NULL, spec TEXT NOT NULL, status TEXT NOT NULL, progress REAL NOT"
            " NULL DEFAULT 0, attempts INTEGER NOT NULL DEFAULT 0, requeues INTEGER NOT NULL"
            " DEFAULT 0, worker_deaths INTEGER NOT NULL DEFAULT 0, sim_seconds REAL NOT NULL,"
            " created_at TEXT NOT NULL, started_at TEXT, finished_at TEXT, error TEXT, note"
            " TEXT); PRAGMA user_version = 2;"
        )
        for job_id, requeues, deaths in (("a", 1, 0), ("b", 0, 1), ("c", 1, 2)):
            conn.execute(
                "INSERT INTO jobs (id, kind, spec, status, requeues, worker_deaths, sim_seconds,"
                " created_at) VALUES (?, 'run', '{}', 'running', ?, ?, 1.0, '2026-11-28Z')",
                (job_id, requeues, deaths),
            )
    s = JobStore(path)
    s.init()
    rows = [s.get(j) for j in "abc"]
    assert [r.requeues for r in rows if r is not None] == [1, 1, 2]
    # restarts kept their count: "a" and "c" have spent max_requeues = 1, "b" has not
    assert s.recover_interrupted(max_requeues=1) == (["b"], ["a", "c"])


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


# Fields the API bounds tighter than the core, on purpose (the schema says why): the core
# accepts any positive mass and a step up to 0.01 s, but outside these ranges a job cannot
# run (dt) or does not describe an insect (mass). Everything else is the core's own bound,
# read from RunSpec by the schema (nothing is retyped, so nothing needs keeping in sync).
TIGHTER = {"body_mass_g": {"ge": 0.5, "le": 30.0}, "dt_s": {"gt": 0.0, "le": 1e-3}}


@pytest.mark.parametrize(
    "name", ["beta", "body_mass_g", "slope_deg", "duration_s", "dt_s", "control_dt_s", "d31_init"]
)
def test_the_api_is_never_looser_than_the_core(name: str) -> None:
    """The API refuses at the door what the core would refuse later, and more only where
    TIGHTER says so (and then within the core's range)."""
    core = _bounds(RunSpec.model_fields[name].metadata)
    if name == "d31_init":
        mine = _bounds(list(D31.__metadata__[0].metadata))
    else:
        mine = _bounds(RunJob.model_fields[name].metadata)
    if name not in TIGHTER:
        assert mine == core
        return
    assert mine == TIGHTER[name]
    lo_core = core.get("gt", core.get("ge", -math.inf))
    assert mine.get("gt", mine.get("ge", -math.inf)) >= lo_core
    assert mine.get("lt", mine.get("le", math.inf)) <= core.get("lt", core.get("le", math.inf))


def test_delete_only_finished_jobs_with_their_result(store: JobStore) -> None:
    queued, done = _submit(store), _submit(store)
    store.cancel(queued)
    running = _submit(store)
    claim = store.claim_next()
    assert claim is not None and claim.job_id == done
    assert store.finish_done(claim, {"records": [1]})
    store.claim_next()  # `running` is now running
    assert store.delete_finished(running)[0] == "running" and store.get(running) is not None
    assert store.delete_finished(done)[0] == "done"
    assert store.get(done) is None and store.result(done) is None
    with sqlite3.connect(store.path) as conn:
        assert conn.execute("SELECT count(*) FROM results").fetchone()[0] == 0
    assert store.delete_finished("nope") == ("missing", None)


def test_retention_keeps_the_newest_finished_and_all_active(store: JobStore) -> None:
    ids = [_submit(store) for _ in range(5)]
    for job_id in ids[:4]:
        store.cancel(job_id)
    assert store.purge_finished(None, keep=2) == 2
    left = {j.id for j in store.list_jobs(None, 10, 0)[0]}
    assert left == {ids[2], ids[3], ids[4]}  # two newest finished + the queued one
    # age: nothing finished more than a day ago, until one is back-dated by three days
    assert store.purge_finished(1.0, None) == 0
    with sqlite3.connect(store.path) as conn:
        conn.execute(
            "UPDATE jobs SET finished_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now', '-3 days')"
            " WHERE id = ?",
            (ids[2],),
        )
    assert store.purge_finished(2.0, None) == 1
    assert {j.id for j in store.list_jobs(None, 10, 0)[0]} == {ids[3], ids[4]}
    assert store.purge_finished(None, keep=0) == 1
    assert {j.id for j in store.list_jobs(None, 10, 0)[0]} == {ids[4]}


def test_remaining_time_from_progress_or_history() -> None:
    # from its own rate: 10 s for the first 25 % -> 30 s more
    assert estimates.remaining_s(
        elapsed_s=10, progress=0.25, sim_seconds=100, wall_per_sim_s=None
    ) == pytest.approx(30.0)
    # no progress yet: recent jobs ran at 0.2 wall s per sim s -> 100 x 0.2 - 5
    assert estimates.remaining_s(
        elapsed_s=5, progress=0.0, sim_seconds=100, wall_per_sim_s=0.2
    ) == pytest.approx(15.0)
    assert estimates.remaining_s(elapsed_s=5, progress=1.0, sim_seconds=1, wall_per_sim_s=1) == 0


def test_the_estimate_counts_the_step() -> None:
    """Issue 30: eta_s ignored dt_s, so a job at 1e-6 s was estimated as one at the default
    5e-5 s, 50 times too short. Both the job's size and the history rate are step-weighted."""
    from dataclasses import replace
    from datetime import UTC, datetime

    now = datetime.now(UTC)
    started = now.isoformat().replace("+00:00", "Z")
    job = JobRow(id="j", kind="run", spec={"kind": "run"}, status=JobStatus.RUNNING,
                 progress=0.0, attempts=1, requeues=0, sim_seconds=10.0, created_at=started,
                 started_at=started, finished_at=None, error=None, note=None)  # fmt: skip
    fine = replace(job, spec={"kind": "run", "dt_s": 1e-6, "control_dt_s": 5e-4})
    default = estimates.eta_of(job, now, 0.5)
    assert default == pytest.approx(5.0, abs=0.2)
    assert estimates.eta_of(fine, now, 0.5) == pytest.approx(50 * default, rel=0.05)
    # a done job at 1e-5 s (5x the steps) that took 50 s for 10 s: 1 wall s per default-step s
    assert estimates.wall_per_sim_second([(50.0, 10.0, {"dt_s": 1e-5})]) == pytest.approx(1.0)
    assert estimates.wall_per_sim_second([]) is None


def test_retry_after_is_the_soonest_free_worker() -> None:
    assert estimates.retry_after_s(workers=2, running_remaining_s=[45.2, 30.1]) == 31
    assert estimates.retry_after_s(workers=2, running_remaining_s=[45.2]) == 1  # one idle
    assert estimates.retry_after_s(workers=0, running_remaining_s=[]) == 60
    assert estimates.retry_after_s(workers=1, running_remaining_s=[1e6]) == 3600
    assert estimates.retry_after_s(workers=1, running_remaining_s=[0.0]) == 1


def test_error_messages_carry_no_paths_or_tracebacks() -> None:
    raw = (
        "Traceback (most recent call last):\n"
        '  File "/opt/venv/lib/python3.11/site-packages/pydantic/main.py", line 253, in f\n'
        "ValueError: 1 validation error for RunSpec\n  Input should be greater than 0 "
        "[type=greater_than]\n    For further information visit "
        "https://errors.pydantic.dev/2.11/v/greater_than (at /work/x/server/kinds.py:42)"
    )
    out = errors.sanitize(raw)
    assert "/" not in out.replace("kinds.py", "") and "Traceback" not in out
    assert "File " not in out and "https" not in out
    assert "Input should be greater than 0" in out and "kinds.py:42" in out
    try:
        RunSpec(duration_s=0)
    except Exception as exc:
        msg = errors.exception_message(exc)
        assert msg.startswith("invalid job: duration_s:")
        assert "site-packages" not in msg and "http" not in msg


def test_advice_is_chosen_from_the_failure_kind() -> None:
    flip = [RunFailure("flipped", 0.26, "implicitfast", 5e-5, "body flipped (up-axis z 0.49)")]
    steep = RunJob(slope_deg=80.0)
    assert "smaller dt_s will not help" in common.advice(steep, flip)
    coarse = RunJob(slope_deg=80.0, dt_s=4e-4, control_dt_s=4e-4)
    assert "try a smaller dt_s" in common.advice(coarse, flip)
    # the kind decides, not the words: a numerical kind whose reason names nothing numerical
    blowup = [RunFailure("mujoco_warning", 0.01, "implicitfast", 5e-5, "anything")]
    assert "try a smaller dt_s" in common.advice(RunJob(), blowup)
    worded = [RunFailure("on_floor", 0.3, "implicitfast", 5e-5, "MuJoCo warning non-finite")]
    assert "smaller dt_s will not help" in common.advice(RunJob(), worded)


def test_floats_come_back_tidy() -> None:
    assert bounds.tidy(0.6599999999999999) == 0.66
    assert bounds.tidy(1.234567890123456e-7) == 1.23456789012e-7
    job = SweepJob(beta_range={"start": 0.62, "stop": 0.70, "steps": 5})
    assert job.beta_range.values() == [0.62, 0.64, 0.66, 0.68, 0.7]


def test_sweep_size_counts_grid_times_list() -> None:
    job = SweepJob(beta_range={"start": 0.6, "stop": 0.7, "steps": 5}, d31_init=[1.0, 2.0])
    assert job.run_count() == 10
    assert job.total_sim_seconds() == pytest.approx(10 * job.duration_s)
    assert job.beta_range.values()[0] == 0.6 and job.beta_range.values()[-1] == pytest.approx(0.7)


def test_a_version_3_store_gains_the_counts_and_the_ledger(tmp_path: Path) -> None:
    """Version 4 adds the job's simulation counts (null for jobs stored before) and the tables
    of idempotency keys and tombstones; an old file gains them on open, its jobs intact."""
    path = tmp_path / "v3.sqlite3"
    with sqlite3.connect(path) as conn:
        conn.executescript(
            "CREATE TABLE jobs (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE,"
            " kind TEXT NOT NULL, spec TEXT NOT NULL, status TEXT NOT NULL, progress REAL NOT"
            " NULL DEFAULT 0, attempts INTEGER NOT NULL DEFAULT 0, requeues INTEGER NOT NULL"
            " DEFAULT 0, worker_deaths INTEGER NOT NULL DEFAULT 0, restarts INTEGER NOT NULL"
            " DEFAULT 0, moving_since TEXT, sim_seconds REAL NOT NULL, created_at TEXT NOT NULL,"
            " started_at TEXT, finished_at TEXT, error TEXT, note TEXT);"
            " CREATE TABLE results (job_id TEXT PRIMARY KEY REFERENCES jobs (id) ON DELETE"
            " CASCADE, body BLOB NOT NULL); PRAGMA user_version = 3;"
        )
        conn.execute("INSERT INTO jobs (id, kind, spec, status, sim_seconds, created_at) VALUES"
                     " ('old', 'run', '{}', 'done', 1.0, '2026-11-28T00:00:00Z')")  # fmt: skip
    s = JobStore(path)
    s.init()
    with sqlite3.connect(path) as conn:
        assert conn.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION == 4
    old = s.get("old")
    assert old is not None and old.status is JobStatus.DONE and old.simulations is None
    # the new parts work on the migrated file: counts on finish, keys, tombstones
    key = IdempotencyKey("k", "digest", 60.0)
    made = s.submit("run", {"kind": "run"}, 1.0, 10, key)
    assert isinstance(made, JobRow)
    again = s.submit("run", {"kind": "run"}, 1.0, 10, key)
    assert isinstance(again, Replayed) and again.job is not None and again.job.id == made.id
    claim = s.claim_next()
    assert claim is not None and claim.job_id == made.id
    sims = Simulations(tasks=3, computed=1, from_cache=2, backend="inline")
    assert s.finish_done(claim, {"records": []}, sims)
    done = s.get(made.id)
    assert done is not None and done.simulations == sims
    assert s.delete_finished("old")[0] == "done" and s.get("old") is None
    gone = s.gone("old", None)
    assert gone is not None and gone.kind == "run" and "by request" in gone.sentence()

"""The job store: one SQLite file (WAL mode) is the queue, the job table and the result store
(and the ledger of idempotency keys and tombstones, `server.ledger`).

Why the job table is also the queue: the state a client sees and the state workers act on can
then never disagree, even after `kill -9`. A job moves queued -> running -> done | failed, or to
cancelled from queued or running. Every write a worker makes is fenced by the job's `attempts`
counter and `status = 'running'`, so a worker that lost its job (cancelled, re-queued after a
crash) cannot overwrite what happened since.

The API process and the worker processes each open their own connections; WAL lets readers
(status polls) proceed while a worker commits a result.
"""

from __future__ import annotations

import json
import sqlite3
import threading
import uuid
import zlib
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from server import ledger
from server.jobrows import (
    COLUMNS,
    FINISHED_SQL,
    MIGRATIONS,
    SCHEMA,
    SCHEMA_VERSION,
    Claim,
    IdempotencyKey,
    JobRow,
    KeyConflict,
    Missing,
    QueueFull,
    Replayed,
    Simulations,
    now_iso,
)
from server.ledger import Tombstone
from server.status import ACTIVE, FINISHED, JobStatus, sql_list

__all__ = [
    "SCHEMA_VERSION",
    "Claim",
    "IdempotencyKey",
    "JobRow",
    "JobStore",
    "KeyConflict",
    "QueueFull",
    "Replayed",
    "Simulations",
    "now_iso",
]

# how many times a job may lose its worker to an outside kill and still be run again
MAX_WORKER_DEATHS = 1

# Every write a worker makes holds only while its claim does: same attempt, still running.
_FENCE = "id = ? AND attempts = ? AND status = ?"


def _fence(claim: Claim) -> tuple[str, int, JobStatus]:
    return claim.job_id, claim.attempt, JobStatus.RUNNING


class JobStore:
    """The queries (the tables: `server.jobrows`; the keys and tombstones: `server.ledger`).
    Safe to use from many threads (one connection per thread)."""

    def __init__(self, path: Path | str) -> None:
        self.path = Path(path)
        self._local = threading.local()

    # ---- connections ---------------------------------------------------------------------

    def _conn(self) -> sqlite3.Connection:
        conn: sqlite3.Connection | None = getattr(self._local, "conn", None)
        if conn is None:
            conn = sqlite3.connect(self.path, timeout=10.0, isolation_level=None)
            conn.row_factory = sqlite3.Row
            conn.execute("PRAGMA busy_timeout = 10000")
            conn.execute("PRAGMA foreign_keys = ON")
            # NORMAL is safe against a killed process in WAL mode (only power loss can lose
            # the last commits), and it keeps status polls fast while workers write.
            conn.execute("PRAGMA synchronous = NORMAL")
            self._local.conn = conn
        return conn

    @contextmanager
    def _write(self) -> Iterator[sqlite3.Connection]:
        """BEGIN IMMEDIATE: take the write lock up front so check-then-write is atomic."""
        conn = self._conn()
        conn.execute("BEGIN IMMEDIATE")
        try:
            yield conn
        except BaseException:
            conn.execute("ROLLBACK")
            raise
        else:
            conn.execute("COMMIT")

    def close(self) -> None:
        conn = getattr(self._local, "conn", None)
        if conn is not None:
            conn.close()
            self._local.conn = None

    def init(self) -> None:
        """Create the file and tables; switch to WAL (a property of the file, set once)."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        conn = self._conn()
        mode = conn.execute("PRAGMA journal_mode = WAL").fetchone()[0]
        if str(mode).lower() != "wal":
            raise RuntimeError(f"could not switch {self.path} to WAL mode (got {mode!r})")
        conn.executescript(SCHEMA)
        version = conn.execute("PRAGMA user_version").fetchone()[0]
        if version == 0:  # a new file: the schema above is the current one
            conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
            return
        if version > SCHEMA_VERSION:
            raise RuntimeError(
                f"{self.path} has schema version {version}; this server reads {SCHEMA_VERSION}"
            )
        for step in range(version, SCHEMA_VERSION):  # columns with defaults, added in place
            with self._write() as w:
                for sql in MIGRATIONS[step]:
                    w.execute(sql)
                w.execute(f"PRAGMA user_version = {step + 1}")

    # ---- API side ------------------------------------------------------------------------

    def submit(
        self,
        kind: str,
        spec: dict[str, Any],
        sim_seconds: float,
        queue_limit: int,
        key: IdempotencyKey | None = None,
    ) -> JobRow | QueueFull | Replayed | KeyConflict:
        """Insert a queued job unless the queue is full or `key` made a job already (that job,
        or a conflict if its body differs); the checks and the insert are one lock."""
        job_id = str(uuid.uuid4())
        with self._write() as conn:
            if key is not None:
                seen = ledger.find_key(conn, key.key, key.digest, key.ttl_s)
                if seen is not None and not seen.same_body:
                    return KeyConflict(seen.job_id, seen.created_at)
                if seen is not None:
                    row = conn.execute(f"SELECT {COLUMNS} FROM jobs WHERE id = ?",
                                       (seen.job_id,)).fetchone()  # fmt: skip
                    gone = None if row else ledger.tombstone(conn, seen.job_id, None)
                    return Replayed(JobRow.from_sql(row) if row else None, gone, seen.created_at)
            queued = conn.execute(
                "SELECT count(*) FROM jobs WHERE status = ?", (JobStatus.QUEUED,)
            ).fetchone()
            if queued[0] >= queue_limit:
                return QueueFull(queued=int(queued[0]))
            conn.execute(
                "INSERT INTO jobs (id, kind, spec, status, sim_seconds, created_at)"
                " VALUES (?, ?, ?, ?, ?, ?)",
                (job_id, kind, json.dumps(spec), JobStatus.QUEUED, sim_seconds, now_iso()),
            )
            if key is not None:
                ledger.remember_key(conn, key.key, job_id, key.digest, now_iso())
        job = self.get(job_id)
        assert job is not None
        return job

    def get(self, job_id: str) -> JobRow | None:
        row = self._conn().execute(f"SELECT {COLUMNS} FROM jobs WHERE id = ?", (job_id,)).fetchone()
        return JobRow.from_sql(row) if row is not None else None

    def list_jobs(
        self, status: JobStatus | None, limit: int, offset: int
    ) -> tuple[list[JobRow], int]:
        """Newest first."""
        conn = self._conn()
        where, args = ("WHERE status = ?", (status,)) if status else ("", ())
        total = conn.execute(f"SELECT count(*) FROM jobs {where}", args).fetchone()[0]
        rows = conn.execute(
            f"SELECT {COLUMNS} FROM jobs {where} ORDER BY seq DESC LIMIT ? OFFSET ?",
            (*args, limit, offset),
        ).fetchall()
        return [JobRow.from_sql(r) for r in rows], int(total)

    def cancel(self, job_id: str) -> tuple[JobStatus | Missing, JobRow | None]:
        """-> (previous status or 'missing', job). Only queued and running jobs change."""
        with self._write() as conn:
            row = conn.execute("SELECT status FROM jobs WHERE id = ?", (job_id,)).fetchone()
            if row is None:
                return "missing", None
            previous = JobStatus(row[0])
            if previous in ACTIVE:
                conn.execute(
                    "UPDATE jobs SET status = ?, finished_at = ?,"
                    " note = coalesce(note || ' ', '') || ? WHERE id = ?",
                    (
                        JobStatus.CANCELLED,
                        now_iso(),
                        f"cancelled by request while {previous}.",
                        job_id,
                    ),
                )
        return previous, self.get(job_id)

    def delete_finished(self, job_id: str) -> tuple[JobStatus | Missing, JobRow | None]:
        """-> (status or 'missing', the job as it was). Only finished jobs are deleted, with
        their result (ON DELETE CASCADE), leaving a tombstone (`gone`)."""
        with self._write() as conn:
            row = conn.execute(f"SELECT {COLUMNS} FROM jobs WHERE id = ?", (job_id,)).fetchone()
            if row is None:
                return "missing", None
            job = JobRow.from_sql(row)
            if job.status in FINISHED:
                ledger.bury(conn, "id = ?", (job_id,), "by request (DELETE ?purge=true)",
                            now_iso())  # fmt: skip
        return job.status, job

    def purge_finished(self, older_than_days: float | None, keep: int | None) -> int:
        """Retention: delete finished jobs finished more than `older_than_days` ago, and all
        but the newest `keep` finished jobs, each leaving a tombstone that names the rule.
        Queued and running jobs are never touched."""
        deleted = 0
        with self._write() as conn:
            if older_than_days is not None:
                deleted += ledger.bury(
                    conn, f"status IN ({FINISHED_SQL})"
                    " AND julianday(finished_at) < julianday('now') - ?", (older_than_days,),
                    f"by retention (finished more than retention_days = {older_than_days:g} "
                    "days before)", now_iso(),
                )  # fmt: skip
            if keep is not None:
                deleted += ledger.bury(
                    conn, f"status IN ({FINISHED_SQL}) AND seq NOT IN (SELECT seq FROM jobs"
                    f" WHERE status IN ({FINISHED_SQL}) ORDER BY seq DESC LIMIT ?)", (keep,),
                    f"by retention (only the newest retention_count = {keep} finished jobs "
                    "are kept)", now_iso(),
                )  # fmt: skip
        return deleted

    def gone(self, job_id: str, tombstone_days: float | None) -> Tombstone | None:
        """Why `job_id` is not here if it was deleted less than `tombstone_days` ago."""
        return ledger.tombstone(self._conn(), job_id, tombstone_days)

    def forget_expired(self, key_ttl_s: float, tombstone_days: float | None) -> int:
        """Housekeeping: idempotency keys past their time to live and old tombstones go."""
        with self._write() as conn:
            return ledger.forget(conn, key_ttl_s, tombstone_days)

    def running_jobs(self) -> list[JobRow]:
        """Every running job (for the estimates)."""
        rows = self._conn().execute(
            f"SELECT {COLUMNS} FROM jobs WHERE status = ?", (JobStatus.RUNNING,)
        )
        return [JobRow.from_sql(r) for r in rows]

    def recent_done(self, limit: int = 20) -> list[tuple[float, float, dict[str, Any]]]:
        """(wall seconds, simulated seconds, spec) of the last `limit` done jobs: what a job
        that has not reported progress yet is estimated from (`estimates.wall_per_sim_second`)."""
        rows = (
            self._conn()
            .execute(
                "SELECT (julianday(finished_at) - julianday(started_at)) * 86400.0, sim_seconds,"
                " spec FROM jobs WHERE status = ? AND started_at IS NOT NULL"
                " AND sim_seconds > 0 ORDER BY seq DESC LIMIT ?",
                (JobStatus.DONE, limit),
            )
            .fetchall()
        )
        return [(float(w), float(s), json.loads(spec)) for w, s, spec in rows if w is not None]

    def result(self, job_id: str) -> dict[str, Any] | None:
        row = (
            self._conn().execute("SELECT body FROM results WHERE job_id = ?", (job_id,)).fetchone()
        )
        if row is None:
            return None
        out: dict[str, Any] = json.loads(zlib.decompress(row[0]))
        return out

    def counts(self) -> dict[JobStatus, int]:
        """Queued and running jobs (the active statuses), each counted."""
        rows = self._conn().execute(
            f"SELECT status, count(*) FROM jobs WHERE status IN ({sql_list(ACTIVE)})"
            " GROUP BY status"
        )
        out = dict.fromkeys(sorted(ACTIVE, key=list(JobStatus).index), 0)
        out.update({JobStatus(s): int(n) for s, n in rows})
        return out

    def typical_job_seconds(self) -> float | None:
        """Median wall time of the last finished jobs, for Retry-After estimates."""
        rows = (
            self._conn()
            .execute(
                "SELECT (julianday(finished_at) - julianday(started_at)) * 86400.0 FROM jobs"
                " WHERE status = ? AND started_at IS NOT NULL"
                " ORDER BY seq DESC LIMIT 20",
                (JobStatus.DONE,),
            )
            .fetchall()
        )
        xs = sorted(float(r[0]) for r in rows if r[0] is not None)
        return xs[len(xs) // 2] if xs else None

    # ---- supervisor side -----------------------------------------------------------------

    def claim_next(self) -> Claim | None:
        """Oldest queued job -> running, atomically; its new attempt number fences the worker."""
        # a plain read first: an idle pool polls this, and must not take the write lock for it
        if (
            self._conn()
            .execute("SELECT 1 FROM jobs WHERE status = ? LIMIT 1", (JobStatus.QUEUED,))
            .fetchone()
            is None
        ):
            return None
        with self._write() as conn:
            row = conn.execute(
                "UPDATE jobs SET status = ?, attempts = attempts + 1, progress = 0,"
                " started_at = ?, finished_at = NULL, moving_since = NULL"
                " WHERE seq = (SELECT seq FROM jobs WHERE status = ? ORDER BY seq LIMIT 1)"
                " RETURNING id, attempts",
                (JobStatus.RUNNING, now_iso(), JobStatus.QUEUED),
            ).fetchone()
        return Claim(str(row[0]), int(row[1])) if row is not None else None

    def recover_interrupted(self, max_requeues: int) -> tuple[list[str], list[str]]:
        """At start-up: jobs left 'running' by a dead server are re-queued, or failed with why.

        Called only while holding the instance lock, so no live worker owns them. A job that
        was running when the server died may itself be the reason it died (memory, a crash),
        so it is re-queued at most `max_requeues` times (counted in `restarts`; `requeues`
        counts these and the re-queues after a worker died).
        """
        requeued: list[str] = []
        failed: list[str] = []
        with self._write() as conn:
            rows = conn.execute(
                "SELECT id, restarts, attempts FROM jobs WHERE status = ? ORDER BY seq",
                (JobStatus.RUNNING,),
            ).fetchall()
            stamp = now_iso()
            for job_id, restarts, attempts in rows:
                if restarts < max_requeues:
                    conn.execute(
                        "UPDATE jobs SET status = ?, progress = 0, started_at = NULL,"
                        " restarts = restarts + 1, requeues = requeues + 1,"
                        " note = coalesce(note || ' ', '') || ?"
                        " WHERE id = ?",
                        (
                            JobStatus.QUEUED,
                            f"re-queued at {stamp}: the server stopped while attempt "
                            f"{attempts} was running.",
                            job_id,
                        ),
                    )
                    requeued.append(job_id)
                else:
                    conn.execute(
                        "UPDATE jobs SET status = ?, finished_at = ?, error = ? WHERE id = ?",
                        (
                            JobStatus.FAILED,
                            stamp,
                            f"the server stopped while this job was running, {restarts + 1} "
                            f"time(s); not re-queued again (limit max_requeues = "
                            f"{max_requeues}), the job may be what brings the server down",
                            job_id,
                        ),
                    )
                    failed.append(job_id)
        return requeued, failed

    def requeue_on_shutdown(self, claim: Claim) -> bool:
        """A clean shutdown interrupted this job: it goes back to the queue, no requeue spent."""
        with self._write() as conn:
            cur = conn.execute(
                "UPDATE jobs SET status = ?, progress = 0, started_at = NULL,"
                " note = coalesce(note || ' ', '') || ?"
                f" WHERE {_FENCE}",
                (
                    JobStatus.QUEUED,
                    f"re-queued at {now_iso()}: the server shut down while it ran.",
                    *_fence(claim),
                ),
            )
        return cur.rowcount == 1

    def status_of(self, job_ids: list[str]) -> dict[str, JobStatus]:
        if not job_ids:
            return {}
        marks = ",".join("?" * len(job_ids))
        rows = self._conn().execute(f"SELECT id, status FROM jobs WHERE id IN ({marks})", job_ids)
        return {str(i): JobStatus(s) for i, s in rows}

    # ---- worker side ---------------------------------------------------------------------

    def spec_of(self, job_id: str) -> dict[str, Any] | None:
        row = self._conn().execute("SELECT spec FROM jobs WHERE id = ?", (job_id,)).fetchone()
        return json.loads(row[0]) if row is not None else None

    def set_progress(self, claim: Claim, fraction: float) -> bool:
        """The attempt's progress; the first above 0 also stamps `moving_since`."""
        x = min(max(float(fraction), 0.0), 1.0)
        cur = self._conn().execute(
            "UPDATE jobs SET progress = ?,"
            " moving_since = coalesce(moving_since, CASE WHEN ? > 0 THEN ? END)"
            f" WHERE {_FENCE}",
            (x, x, now_iso(), *_fence(claim)),
        )
        return cur.rowcount == 1

    def finish_done(
        self, claim: Claim, result: dict[str, Any], sims: Simulations | None = None
    ) -> bool:
        """Store the result and mark done in one transaction, only if the claim still holds;
        `sims`: what the job simulated (shown on its record)."""
        body = zlib.compress(json.dumps(result, allow_nan=False).encode(), 6)
        with self._write() as conn:
            cur = conn.execute(
                f"UPDATE jobs SET status = ?, progress = 1, finished_at = ?, {_SIMS_SET}"
                f" WHERE {_FENCE}",
                (JobStatus.DONE, now_iso(), *_sims(sims), *_fence(claim)),
            )
            if cur.rowcount != 1:
                return False
            conn.execute(
                "INSERT OR REPLACE INTO results (job_id, body) VALUES (?, ?)",
                (claim.job_id, body),
            )
        return True

    def worker_died(self, claim: Claim, reason: str) -> str:
        """The worker running `claim` died from outside (a kill, the OOM killer): the job goes
        back to the queue to run on a fresh worker, its reason kept in the note, unless it has
        lost `MAX_WORKER_DEATHS` workers already: then it fails with every reason (a job that
        kills its worker each time must not take the pool down with it). A re-queue counts in
        `requeues`, as a restart's does. Returns "requeued",
        "failed", or "gone" when the claim no longer holds (cancelled, already finished)."""
        with self._write() as conn:
            row = conn.execute(
                f"SELECT worker_deaths, note FROM jobs WHERE {_FENCE}", _fence(claim)
            ).fetchone()
            if row is None:
                return "gone"
            deaths, note = int(row[0]) + 1, row[1] or ""
            said = f"attempt {claim.attempt}: {reason}"
            if deaths <= MAX_WORKER_DEATHS:
                conn.execute(
                    "UPDATE jobs SET status = ?, progress = 0, started_at = NULL,"
                    " worker_deaths = ?, requeues = requeues + 1,"
                    " note = coalesce(note || ' ', '') || ?"
                    f" WHERE {_FENCE}",
                    (JobStatus.QUEUED, deaths,
                     f"re-queued at {now_iso()} to run on a fresh worker ({said}).",
                     *_fence(claim)),
                )  # fmt: skip
                return "requeued"
            before = [part for part in note.split("re-queued at ") if "fresh worker" in part]
            earlier = "; ".join(p.split("(", 1)[-1].rstrip(". )") for p in before)
            conn.execute(
                "UPDATE jobs SET status = ?, finished_at = ?, error = ?, worker_deaths = ?"
                f" WHERE {_FENCE}",
                (JobStatus.FAILED, now_iso(),
                 f"the job's worker died {deaths} times, so it is not run again (the job may be "
                 f"what kills it): {earlier}; {said}", deaths, *_fence(claim)),
            )  # fmt: skip
            return "failed"

    def finish_failed(self, claim: Claim, error: str, sims: Simulations | None = None) -> bool:
        with self._write() as conn:
            cur = conn.execute(
                f"UPDATE jobs SET status = ?, finished_at = ?, error = ?, {_SIMS_SET}"
                f" WHERE {_FENCE}",
                (JobStatus.FAILED, now_iso(), error, *_sims(sims), *_fence(claim)),
            )
        return cur.rowcount == 1


_SIMS_SET = "sims_tasks = ?, sims_computed = ?, sims_cached = ?, sims_backend = ?"


def _sims(sims: Simulations | None) -> tuple[int | str | None, ...]:
    if sims is None:
        return (None, None, None, None)
    return (sims.tasks, sims.computed, sims.from_cache, sims.backend)

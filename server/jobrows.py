"""The job store's schema and what it returns: the tables (and how an older file gains the
columns, `MIGRATIONS`), a job's row as the store returns it (`JobRow`, with the counts of its
simulations, `Simulations`), and the answers of `JobStore.submit` and the claims it hands out.
Apart from `server.jobs` (the store's SQL) because they change together with the tables, not
with the queries.
"""

from __future__ import annotations

import json
import sqlite3
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from server.ledger import TABLES as LEDGER_TABLES
from server.ledger import Tombstone
from server.status import FINISHED, JobStatus, sql_list

# 2: jobs.worker_deaths (a job whose worker died from outside runs again once); 3: jobs.restarts
# (the server stopped while it ran), so that `requeues` counts every re-queue after a crash
# (the server's or the worker's) while each kind of crash keeps its own limit, and
# jobs.moving_since (when the attempt first reported progress: its rate is measured from there,
# not from a start-up the job's size does not scale); 4: jobs.sims_* (the job's simulations:
# asked for, computed, read from the result cache, and the backend), and the tables of
# idempotency keys and tombstones (`server.ledger`). An older file gains the columns on open
# (`MIGRATIONS`; new tables are created by the schema's CREATE IF NOT EXISTS).
SCHEMA_VERSION = 4
SCHEMA = f"""
CREATE TABLE IF NOT EXISTS jobs (
    seq         INTEGER PRIMARY KEY AUTOINCREMENT,
    id          TEXT NOT NULL UNIQUE,
    kind        TEXT NOT NULL,
    spec        TEXT NOT NULL,
    status      TEXT NOT NULL CHECK (status IN ({sql_list(JobStatus)})),
    progress    REAL NOT NULL DEFAULT 0,
    attempts    INTEGER NOT NULL DEFAULT 0,
    requeues    INTEGER NOT NULL DEFAULT 0,
    worker_deaths INTEGER NOT NULL DEFAULT 0,
    restarts    INTEGER NOT NULL DEFAULT 0,
    moving_since TEXT,
    sim_seconds REAL NOT NULL,
    created_at  TEXT NOT NULL,
    started_at  TEXT,
    finished_at TEXT,
    error       TEXT,
    note        TEXT,
    sims_tasks  INTEGER,
    sims_computed INTEGER,
    sims_cached INTEGER,
    sims_backend TEXT
);
CREATE INDEX IF NOT EXISTS jobs_status_seq ON jobs (status, seq);
CREATE TABLE IF NOT EXISTS results (
    job_id TEXT PRIMARY KEY REFERENCES jobs (id) ON DELETE CASCADE,
    body   BLOB NOT NULL
);
{LEDGER_TABLES}"""

# From version k to k + 1, each in one transaction. Version 2's `requeues` counted server
# restarts only, and a worker death re-queued a job at most once (MAX_WORKER_DEATHS was 1 then).
MIGRATIONS = {
    1: ("ALTER TABLE jobs ADD COLUMN worker_deaths INTEGER NOT NULL DEFAULT 0",),
    2: (
        "ALTER TABLE jobs ADD COLUMN restarts INTEGER NOT NULL DEFAULT 0",
        "ALTER TABLE jobs ADD COLUMN moving_since TEXT",
        "UPDATE jobs SET restarts = requeues, requeues = requeues + min(worker_deaths, 1)",
    ),
    3: (
        "ALTER TABLE jobs ADD COLUMN sims_tasks INTEGER",
        "ALTER TABLE jobs ADD COLUMN sims_computed INTEGER",
        "ALTER TABLE jobs ADD COLUMN sims_cached INTEGER",
        "ALTER TABLE jobs ADD COLUMN sims_backend TEXT",
    ),
}

COLUMNS = (
    "id, kind, spec, status, progress, attempts, requeues, sim_seconds, created_at, started_at,"
    " finished_at, error, note, moving_since, sims_tasks, sims_computed, sims_cached,"
    " sims_backend"
)
FINISHED_SQL = sql_list(FINISHED)
Missing = Literal["missing"]  # what cancel and delete_finished report for an unknown id


def now_iso() -> str:
    return datetime.now(UTC).isoformat(timespec="milliseconds").replace("+00:00", "Z")


class Simulations(BaseModel):
    """A job's simulations (its last attempt's), as its record shows them: what it asked for,
    computed and read back from the result cache, and where it computed them."""

    model_config = ConfigDict(frozen=True)

    tasks: int = Field(
        description="distinct simulations the job asked for (a surface's refinement passes "
        "each count theirs)"
    )
    computed: int = Field(description="simulations this attempt computed")
    from_cache: int = Field(
        description="simulations read back from the result cache instead: finished before by "
        "another job, the command line, or an interrupted attempt of this job"
    )
    backend: str = Field(
        description="where they were computed: inline (the worker process) or dask (the "
        "cluster at the server's dask_address)"
    )


@dataclass(frozen=True)
class JobRow:
    """One row of the job table as the store returns it (times as ISO 8601 UTC text)."""

    id: str
    kind: str
    spec: dict[str, Any]
    status: JobStatus
    progress: float
    attempts: int
    requeues: int
    sim_seconds: float
    created_at: str
    started_at: str | None
    finished_at: str | None
    error: str | None
    note: str | None
    moving_since: str | None = None  # when this attempt first reported progress above 0
    simulations: Simulations | None = None  # what its last attempt simulated, once it ended

    @classmethod
    def from_sql(cls, row: sqlite3.Row) -> JobRow:
        """From a row selected as `COLUMNS`."""
        sims = None
        if row["sims_tasks"] is not None:
            sims = Simulations(tasks=int(row["sims_tasks"]), computed=int(row["sims_computed"]),
                               from_cache=int(row["sims_cached"]),
                               backend=str(row["sims_backend"]))  # fmt: skip
        return cls(
            id=str(row["id"]),
            kind=str(row["kind"]),
            spec=json.loads(row["spec"]),
            status=JobStatus(row["status"]),
            progress=float(row["progress"]),
            attempts=int(row["attempts"]),
            requeues=int(row["requeues"]),
            sim_seconds=float(row["sim_seconds"]),
            created_at=str(row["created_at"]),
            started_at=row["started_at"],
            finished_at=row["finished_at"],
            error=row["error"],
            note=row["note"],
            moving_since=row["moving_since"],
            simulations=sims,
        )


@dataclass(frozen=True)
class Claim:
    """A job handed to a worker; `attempt` is the fencing token for everything it writes."""

    job_id: str
    attempt: int


@dataclass(frozen=True)
class QueueFull:
    queued: int


@dataclass(frozen=True)
class IdempotencyKey:
    """A POST's Idempotency-Key with its body's hash (`ledger.body_hash`), remembered for
    `ttl_s` seconds."""

    key: str
    digest: str
    ttl_s: float


@dataclass(frozen=True)
class Replayed:
    """A POST whose key made a job already: that job, or its tombstone if it was deleted."""

    job: JobRow | None
    gone: Tombstone | None
    key_created_at: str


@dataclass(frozen=True)
class KeyConflict:
    """A POST whose key made another job, from another body."""

    job_id: str
    key_created_at: str

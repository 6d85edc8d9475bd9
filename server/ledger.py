"""What the job store remembers besides the jobs: idempotency keys and tombstones.

Idempotency keys: a client that retries a POST after a network error (it cannot know whether
the first arrived) sends the same `Idempotency-Key` header both times; the store keeps
key -> (job id, a hash of the validated job spec) for `Settings.idempotency_ttl_s`, and a POST
with a key it still knows returns that job instead of queueing a second one. The same key with
another job spec is a client's bug (a key reused for a new request), refused rather than
guessed at. The check and the insert of the job are one transaction (`JobStore.submit`), so
two retries racing each other still make one job.

Tombstones: a job deleted by retention or by a purge leaves its id, kind and when and why it
went, so that GET on it answers 410 Gone with that sentence rather than a bare 404 (which
would read as "wrong id"); tombstones are forgotten after `Settings.tombstone_days`.

SQL on a connection the store holds (inside its transactions); the tables are in the store's
schema (`server.jobs`).
"""

from __future__ import annotations

import hashlib
import json
import sqlite3
from dataclasses import dataclass
from typing import Any

TABLES = """
CREATE TABLE IF NOT EXISTS idempotency_keys (
    key        TEXT PRIMARY KEY,
    job_id     TEXT NOT NULL,
    body_hash  TEXT NOT NULL,
    created_at TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS tombstones (
    id         TEXT PRIMARY KEY,
    kind       TEXT NOT NULL,
    created_at TEXT NOT NULL,
    deleted_at TEXT NOT NULL,
    why        TEXT NOT NULL
);
"""

# the longest key kept: a UUID is 36 characters, Stripe's limit is 255
MAX_KEY_LENGTH = 255


def body_hash(spec: dict[str, Any]) -> str:
    """sha256 of the validated job spec as canonical JSON: the same job however it was spelled
    (key order, spacing, a default left out or written)."""
    text = json.dumps(spec, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


def key_problem(key: str) -> str | None:
    """Why `key` cannot be an idempotency key, or None."""
    if not key or len(key) > MAX_KEY_LENGTH:
        return f"the Idempotency-Key header must be 1 to {MAX_KEY_LENGTH} characters long"
    if not key.isprintable() or not key.isascii():
        return "the Idempotency-Key header must be printable ASCII (a UUID is a good key)"
    return None


@dataclass(frozen=True)
class KeyUse:
    """A key seen within its time to live: the job it made and whether the body matches."""

    job_id: str
    same_body: bool
    created_at: str


def find_key(conn: sqlite3.Connection, key: str, digest: str, ttl_s: float) -> KeyUse | None:
    """The job `key` made within the last `ttl_s` seconds, or None (unknown or expired)."""
    row = conn.execute(
        "SELECT job_id, body_hash, created_at FROM idempotency_keys WHERE key = ?"
        " AND julianday(created_at) >= julianday('now') - ? / 86400.0",
        (key, ttl_s),
    ).fetchone()
    if row is None:
        return None
    return KeyUse(job_id=str(row[0]), same_body=row[1] == digest, created_at=str(row[2]))


def remember_key(conn: sqlite3.Connection, key: str, job_id: str, digest: str, now: str) -> None:
    """Key -> job (an expired row of the same key is replaced)."""
    conn.execute(
        "INSERT OR REPLACE INTO idempotency_keys (key, job_id, body_hash, created_at)"
        " VALUES (?, ?, ?, ?)",
        (key, job_id, digest, now),
    )


@dataclass(frozen=True)
class Tombstone:
    """A deleted job: its id and kind, when it was created and deleted, and why."""

    id: str
    kind: str
    created_at: str
    deleted_at: str
    why: str

    def sentence(self) -> str:
        return (
            f"job {self.id} ({self.kind}, created {self.created_at}) was deleted at "
            f"{self.deleted_at} {self.why}; its record and result are gone (submit it again "
            "to recompute: its simulations may still be in the result cache)"
        )


def bury(conn: sqlite3.Connection, where: str, args: tuple[Any, ...], why: str, now: str) -> int:
    """Delete the jobs matching `where` (SQL on `jobs`, with `args`), each leaving a
    tombstone that says `why`; returns how many went."""
    ids = [r[0] for r in conn.execute(f"SELECT id FROM jobs WHERE {where}", args)]
    if not ids:
        return 0
    marks = ",".join("?" * len(ids))
    conn.execute(
        "INSERT OR REPLACE INTO tombstones (id, kind, created_at, deleted_at, why)"
        f" SELECT id, kind, created_at, ?, ? FROM jobs WHERE id IN ({marks})",
        (now, why, *ids),
    )
    conn.execute(f"DELETE FROM jobs WHERE id IN ({marks})", ids)
    return len(ids)


def tombstone(conn: sqlite3.Connection, job_id: str, days: float | None) -> Tombstone | None:
    """The tombstone of `job_id` if it is younger than `days` (None: any age)."""
    row = conn.execute(
        "SELECT id, kind, created_at, deleted_at, why FROM tombstones WHERE id = ?"
        " AND (? IS NULL OR julianday(deleted_at) >= julianday('now') - ?)",
        (job_id, days, days),
    ).fetchone()
    return None if row is None else Tombstone(*(str(x) for x in row))


def forget(conn: sqlite3.Connection, ttl_s: float, tombstone_days: float | None) -> int:
    """Drop expired keys and tombstones; how many rows went."""
    n = conn.execute(
        "DELETE FROM idempotency_keys WHERE julianday(created_at) < julianday('now') - ? / 86400.0",
        (ttl_s,),
    ).rowcount
    if tombstone_days is not None:
        n += conn.execute(
            "DELETE FROM tombstones WHERE julianday(deleted_at) < julianday('now') - ?",
            (tombstone_days,),
        ).rowcount
    return n

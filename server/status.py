"""A job's status, spelled once: the store's CHECK constraint and queries, the API's schemas and
the worker pool all read `JobStatus`.

A job moves queued -> running -> done | failed, or to cancelled from queued or running.
"""

from __future__ import annotations

from enum import StrEnum
from typing import TYPE_CHECKING, Literal, TypeAlias


class JobStatus(StrEnum):
    QUEUED = "queued"
    RUNNING = "running"
    DONE = "done"
    FAILED = "failed"
    CANCELLED = "cancelled"


ACTIVE: frozenset[JobStatus] = frozenset({JobStatus.QUEUED, JobStatus.RUNNING})
FINISHED: frozenset[JobStatus] = frozenset(JobStatus) - ACTIVE

# The statuses as the API's schemas spell them: the enum's values as a Literal, so that the
# OpenAPI document lists them inline and a wrong one is a 'literal_error', as it was before the
# enum. Type checkers see str, which a validated value is; JobStatus(value) makes it a member.
if TYPE_CHECKING:
    StatusValue: TypeAlias = str
else:
    StatusValue = Literal[tuple(s.value for s in JobStatus)]


def sql_list(statuses: frozenset[JobStatus] | type[JobStatus]) -> str:
    """`'queued','running'`: statuses as SQL string literals, for a CHECK or an IN (...).
    Only ever called with members of the enum, never with a client's text."""
    return ",".join(f"'{s.value}'" for s in sorted(statuses, key=list(JobStatus).index))

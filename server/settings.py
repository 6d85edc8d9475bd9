"""Service settings, read from the environment (prefix ``INSECT_GAIT_``) or passed in by tests.

Every limit lives here so that an operator can tune a deployment without code changes and the
limits a client is refused with are the same numbers the docs and error messages show.
"""

from __future__ import annotations

import os
from pathlib import Path

from pydantic import Field, SecretStr, field_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

from sim_core import cache_max_bytes_of, default_cache_dir, default_cache_max_bytes


def _default_workers() -> int:
    """Leave one core to the live viewer and the API when they share the machine."""
    return max(1, (os.cpu_count() or 1) - 1)


class Settings(BaseSettings):
    """One deployment's configuration; env var names are the field names upper-cased."""

    model_config = SettingsConfigDict(env_prefix="INSECT_GAIT_", extra="ignore")

    host: str = Field("127.0.0.1", description="interface to bind; loopback unless told")
    port: int = Field(8000, ge=0, le=65535, description="TCP port (0 = any free port)")
    db_path: Path = Field(
        Path("data/insect-gait.sqlite3"), description="SQLite file for jobs and results"
    )
    workers: int = Field(
        default_factory=_default_workers,
        ge=0,
        le=256,
        description="simulation worker processes; 0 keeps jobs queued and runs none; "
        "default: cores - 1 (at least 1), so that the live viewer keeps a core",
    )
    worker_nice: int = Field(
        10,
        ge=0,
        le=19,
        description="OS niceness of the worker processes (0 = as the API; 19 = lowest "
        "priority): simulations yield the CPU to the viewer and the API",
    )
    threads_per_worker: int | None = Field(
        None,
        ge=1,
        le=256,
        description="threads one worker gives simulate_batch; None = cores / workers",
    )
    queue_limit: int = Field(
        100, ge=1, le=100_000, description="queued (not yet running) jobs before 429"
    )
    max_job_sim_seconds: float = Field(
        3600.0, gt=0, description="simulated seconds one job may ask for, summed over its runs"
    )
    max_runs_per_job: int = Field(
        1000, ge=1, description="simulations one job may ask for (list length x grid size)"
    )
    max_requeues: int = Field(
        1,
        ge=0,
        le=10,
        description="times a job interrupted by a server crash is re-queued before it fails",
    )
    retention_days: float | None = Field(
        None,
        gt=0,
        description="finished jobs (done, failed, cancelled) older than this are deleted with "
        "their results; None keeps them",
    )
    retention_count: int | None = Field(
        None,
        ge=0,
        description="at most this many finished jobs are kept (the newest); None keeps all",
    )
    retention_interval_s: float = Field(
        3600.0,
        gt=0,
        le=86400.0,
        description="how often the retention rules are applied (also once at start-up)",
    )
    cache_dir: Path = Field(
        default_factory=default_cache_dir,
        description="the result cache the jobs' simulations are kept in and read back from, "
        "shared with the command line (`insect-gait cache info`); default: the "
        "installation's (INSECT_GAIT_CACHE_DIR, else the checkout's out/cache)",
    )
    cache_max_bytes: int | None = Field(
        default_factory=default_cache_max_bytes,
        ge=0,
        description="size limit of the cache, bytes: after a job the least recently used "
        "results are evicted down to 90% of it; 0 or 'none' = no limit (default 2 GiB)",
    )
    dask_address: str | None = Field(
        None,
        description="a dask.distributed scheduler (tcp://host:8786): the workers send their "
        "jobs' simulations there instead of computing them themselves (needs the cluster "
        "extra); None = each worker computes its jobs",
    )
    idempotency_ttl_s: float = Field(
        86400.0,
        gt=0,
        le=30 * 86400.0,
        description="how long an Idempotency-Key is remembered: a POST with a key seen this "
        "recently returns the job it created; after it, the key is forgotten",
    )
    tombstone_days: float | None = Field(
        90.0,
        gt=0,
        description="how long the id of a deleted job (retention or purge) answers 410 Gone "
        "saying when and why it went; after it, 404; None = for ever",
    )
    api_token: SecretStr | None = Field(
        None, description="when set, mutating endpoints need 'Authorization: Bearer <token>'"
    )
    log_level: str = Field("info", description="uvicorn log level")

    @field_validator("api_token", mode="before")
    @classmethod
    def _empty_token_is_none(cls, v: object) -> object:
        # compose passes INSECT_GAIT_API_TOKEN="" when unset; that must mean "no token",
        # not "the token is the empty string".
        if v is None or (isinstance(v, str) and not v.strip()):
            return None
        return v

    @field_validator("cache_max_bytes", mode="before")
    @classmethod
    def _limit_words(cls, v: object) -> object:
        # the environment's words, read as the command line reads them (0 / none: no limit);
        # compose passes "" when the variable is unset: the default, as for the CLI
        if isinstance(v, str) and not v.strip():
            return default_cache_max_bytes()
        return cache_max_bytes_of(v) if isinstance(v, str) or v == 0 else v

    @field_validator("tombstone_days", mode="before")
    @classmethod
    def _none_is_for_ever(cls, v: object) -> object:
        return None if isinstance(v, str) and v.strip().lower() == "none" else v

    @field_validator("dask_address", mode="before")
    @classmethod
    def _empty_address_is_none(cls, v: object) -> object:
        if v is None or (isinstance(v, str) and not v.strip()):
            return None  # compose passes INSECT_GAIT_DASK_ADDRESS="" outside its profile
        return v

    def threads_for_one_worker(self) -> int:
        """Share the cores among workers so N busy workers do not oversubscribe the machine."""
        if self.threads_per_worker is not None:
            return self.threads_per_worker
        cores = os.cpu_count() or 1
        spare = cores - 1 if cores > 1 else 1  # the viewer's core, as in the default workers
        return max(1, spare // max(1, self.workers))

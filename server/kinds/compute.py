"""Where a job's simulations run and are kept: the installation's result cache and a backend.

Why: every kind's simulations are `sim_core` tasks (`run_task`, `ramp_task`; the surface's
probes and the finder's runs are tasks inside the core's own functions), run by
`sim_core.run_tasks` through the content-keyed cache the command line uses
(`Settings.cache_dir`). So a job submitted twice, or a job that needs simulations another job
or a `reproduce` already ran, reads them back instead of computing them; a job re-run after
its worker was killed resumes from the chunks it had finished (each chunk's results are stored
the moment it returns); and with a Dask scheduler configured (`Settings.dask_address`) the
chunks run on the cluster, their results stored here, so the cluster's workers need no share of
the cache. A task's numbers do not depend on where or with whom it runs (`sim_core.runs`), so
the result bytes are the same on every path.

Progress: run here (the inline backend), each chunk runs through `ChunkProgress.executor`, so
the job's progress moves inside a chunk; on a cluster the chunk runs there, and the job moves
when a chunk comes back (`on_progress`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import sim_core
from server.jobs import Simulations
from server.kinds.base import JobFailed, Progress
from server.kinds.progress import ChunkProgress


@dataclass
class Compute:
    """A job's way to its simulations (built per job by the worker, `open_compute`).

    Args:
        progress: the job's progress callback (the worker's, throttled there), 0..1.
        cache: the shared result cache.
        backend: where chunks run: in this worker (inline) or on a Dask cluster.
        nthread: threads a chunk's physics steps on when it runs here.
    """

    progress: Progress
    cache: sim_core.ResultCache
    backend: sim_core.Backend
    nthread: int = 1
    # a factory, not the class: naming sim_core.RunStats here would load the engine on import
    stats: sim_core.RunStats = field(default_factory=lambda: sim_core.RunStats())

    @property
    def here(self) -> bool:
        """Whether chunks run in this process (so a chunk's progress can be watched)."""
        return self.backend.name == "inline"

    def moving(self, runs: int, report: Progress | None = None) -> ChunkProgress:
        """A progress that moves inside chunks, for `runs` runs, reporting to `report`
        (default: the job's)."""
        return ChunkProgress(report or self.progress, runs, self.nthread)

    def core(self, moving: ChunkProgress) -> dict[str, Any]:
        """The keyword arguments of the core's cached functions (`drift_surface`,
        `surface_atlas`, `sweep`): this cache, backend and count, and the executor."""
        return {
            "cache": self.cache,
            "backend": self.backend,
            "stats": self.stats,
            "executor": moving.executor if self.here else sim_core.execute_chunk,
        }

    def run(
        self, tasks: Sequence[sim_core.Task], report: Progress | None = None
    ) -> list[dict[str, Any]]:
        """Each task's result (`execute_chunk`'s dict), in the order of `tasks`, from the
        cache or computed and stored; `report` (default: the job's progress) hears the share
        of these tasks done."""
        moving = self.moving(len(tasks), report)
        kw = self.core(moving)
        results, stats = sim_core.run_tasks(
            tasks, kw["cache"], kw["backend"], progress=False, executor=kw["executor"],
            on_progress=moving.on_progress,
        )  # fmt: skip
        self.stats.add(stats)
        return [results[t.key] for t in tasks]

    def computed_elsewhere(self, n: int) -> None:
        """Count `n` simulations that ran outside the cache (a kind that cannot use it)."""
        self.stats.add(sim_core.RunStats(tasks=n, computed=n))

    def counts(self) -> Simulations:
        """What the job simulated so far, for its record."""
        s = self.stats
        return Simulations(tasks=s.tasks, computed=s.computed, from_cache=s.cached,
                           backend=self.backend.name)  # fmt: skip


@dataclass(frozen=True)
class ComputeSettings:
    """Where every job of a worker keeps and runs its simulations (from `Settings`): the
    cache folder and its size limit (bytes, None: none), and the Dask scheduler (None: the
    worker computes them itself)."""

    cache_dir: Path
    cache_max_bytes: int | None = None
    dask_address: str | None = None


def open_compute(where: ComputeSettings, progress: Progress, nthread: int) -> Compute:
    """A job's `Compute`: the cache at `where.cache_dir`, on the Dask scheduler at
    `where.dask_address` or in this process. Close its backend when the job ends. Raises
    `JobFailed` saying why when the cluster cannot be used (its extra missing, or no scheduler
    answering)."""
    cache = sim_core.ResultCache(where.cache_dir, max_bytes=where.cache_max_bytes)
    if not where.dask_address:
        return Compute(progress, cache, sim_core.get_backend("inline"), nthread)
    try:
        backend = sim_core.get_backend("dask", address=where.dask_address)
    except sim_core.BackendUnavailable as exc:
        raise JobFailed(f"the server is set to compute on a Dask cluster, but {exc}") from None
    except (OSError, TimeoutError) as exc:
        raise JobFailed(
            f"no Dask scheduler answered at {where.dask_address} (the server's dask_address): "
            f"{exc}; start the cluster (docker compose --profile cluster up) or unset "
            "INSECT_GAIT_DASK_ADDRESS"
        ) from None
    return Compute(progress, cache, backend, nthread)

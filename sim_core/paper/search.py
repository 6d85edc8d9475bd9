"""The finder's searches run as cached tasks on a backend (local pool or Dask).

`task_runner` turns the finder's (cell, probe) requests into `Task`s, so that every finder run
is content-addressed in the result cache (an interrupted search resumes: the rounds it had
finished are read back, and a search is deterministic, so it asks for the same runs again)
and goes to whichever backend `reproduce` or `atlas` was given.
"""

from __future__ import annotations

from typing import Any

from sim_core.contract.finder import Cell, Probe, RunFn
from sim_core.contract.template import RunTemplate
from sim_core.model.params import ModelParams
from sim_core.runs.backends import Backend, Executor, RunStats, run_tasks
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import Task, execute_chunk, run_task


def probe_task(
    cell: Cell, probe: Probe, params: ModelParams | None, *, template: RunTemplate | None = None
) -> Task:
    """The task of one finder run: the run `template` (RunSpec's defaults if None; every field
    but the per-run ones), the cell's beta, mass and slope and the probe's start and length on
    top."""
    return run_task((template or RunTemplate()).spec(**probe.spec_fields(), **cell.spec_fields()),
                    params)  # fmt: skip


def task_runner(
    cache: ResultCache,
    backend: Backend,
    params: ModelParams | None,
    *,
    chunk_size: int = 8,
    progress: bool | str = True,
    stats: RunStats | None = None,
    executor: Executor = execute_chunk,
    template: RunTemplate | None = None,
) -> RunFn:
    """A `RunFn` for `find` that runs each round through the cache on `backend`, every run on
    `template` (`probe_task`); `stats`, if given, accumulates what every round computed and
    read from the cache."""

    def run(batch: list[tuple[Cell, Probe]]) -> list[dict[str, Any]]:
        tasks = [probe_task(c, p, params, template=template) for c, p in batch]
        results, st = run_tasks(tasks, cache, backend, chunk_size, progress, executor)
        if stats is not None:
            stats.tasks += st.tasks
            stats.computed += st.computed
            stats.cached += st.cached
            stats.compute_s += st.compute_s
        return [results[t.key] for t in tasks]

    return run

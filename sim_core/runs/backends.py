"""Where task chunks run: in this process, on a local process pool, or on a Dask cluster.

`run_tasks` is the one loop every backend shares: drop tasks whose result is cached, group the
rest into chunks (`sim_core.runs.tasks.make_chunks`), hand the chunks to a backend, and store each
chunk's results the moment it comes back (so an interrupted run resumes from there), with a tqdm
progress bar over tasks.

Backends:

- `local` (default): a process pool with one single-threaded batch per process and as many
  processes as cores. Why processes rather than one big `simulate_batch` on MuJoCo's thread
  pool: the thread pool parallelises only the physics rollout, while the compiled controller,
  the event bookkeeping and each ramp's live parameter updates run in the calling thread
  between rollouts; and a batch steps in lock-step, so one long ramp would hold a whole batch
  (and its threads) for its full length. Separate processes run everything in parallel and let
  a long ramp occupy one core while the return maps fill the others.
- `dask`: the same chunks as `dask.distributed` futures, on a scheduler at `--address` or on a
  `LocalCluster` started for the run. Dask rather than Ray: it is pure Python and small (one
  pip extra, no native runtime), its `LocalCluster` starts in about a second inside a test,
  and plain futures are all these independent chunks need.
- `inline`: everything in the calling process, one chunk after another (tests, debugging).

Every backend runs the same `execute_chunk` on the same chunks, and a simulation's numbers do
not depend on which batch it shares (see `sim_core.runs.tasks`), so all backends give identical
results.
"""

from __future__ import annotations

import json
import multiprocessing
import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass
from typing import Any, Protocol

from sim_core.runs import BACKENDS
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import Task, execute_chunk, make_chunks

Executor = Callable[[Sequence[Task]], list[dict[str, Any]]]
ChunkResults = Iterator[tuple[list[Task], list[dict[str, Any]]]]
RAY_UNSUPPORTED = (
    "the ray backend is not supported: use --backend dask (optionally --address "
    "tcp://scheduler:8786). We chose Dask distributed because it is pure Python and small "
    "(pip install 'insect-gait[cluster]'), starts a LocalCluster in about a second for tests, "
    "and these independent chunks need nothing beyond plain futures."
)


class BackendUnavailable(RuntimeError):
    """A backend that cannot run here (not supported, or its extra is not installed)."""


class Backend(Protocol):
    name: str
    workers: int

    def imap(self, fn: Executor, chunks: Sequence[list[Task]]) -> ChunkResults:
        """(chunk, its results) as each chunk finishes, in any order."""
        ...

    def close(self) -> None: ...


class InlineBackend:
    """Every chunk in this process, in order."""

    name = "inline"
    workers = 1

    def imap(self, fn: Executor, chunks: Sequence[list[Task]]) -> ChunkResults:
        for chunk in chunks:
            yield chunk, fn(chunk)

    def close(self) -> None:
        pass


class LocalBackend:
    """A pool of `workers` processes (default: all cores); one chunk per process at a time.

    Processes are started with 'spawn' so that no thread state (tqdm's monitor, MuJoCo's
    pools) is forked; the compiled controller loads from numba's on-disk cache in each. The
    pool starts at the first call that needs it and serves every later one until `close`
    (the finder asks in ~20 rounds: one start-up, not twenty). With one worker or one chunk
    it runs inline.
    """

    name = "local"

    def __init__(self, workers: int | None = None) -> None:
        self.workers = max(1, workers or os.cpu_count() or 1)
        self._pool: ProcessPoolExecutor | None = None

    def imap(self, fn: Executor, chunks: Sequence[list[Task]]) -> ChunkResults:
        if self.workers == 1 or len(chunks) <= 1:
            yield from InlineBackend().imap(fn, chunks)
            return
        if self._pool is None:
            ctx = multiprocessing.get_context("spawn")
            self._pool = ProcessPoolExecutor(max_workers=self.workers, mp_context=ctx)
        futures: dict[Future[list[dict[str, Any]]], list[Task]] = {
            self._pool.submit(fn, chunk): chunk for chunk in chunks
        }
        try:
            pending = set(futures)
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for fut in done:
                    yield futures[fut], fut.result()
        except BaseException:  # interrupted or failed: drop what has not started, do not wait
            self._pool.shutdown(wait=False, cancel_futures=True)
            self._pool = None
            raise

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None


class DaskBackend:
    """Chunks as dask.distributed futures; a LocalCluster is started when no address is given.

    processes=False runs the LocalCluster's workers as threads of this process (tests: light
    and quick to start); a real cluster keeps one single-threaded process per core.
    """

    name = "dask"

    def __init__(
        self, address: str | None = None, workers: int | None = None, processes: bool = True
    ) -> None:
        try:
            from distributed import Client, LocalCluster
        except ImportError as exc:
            raise BackendUnavailable(
                "the dask backend needs the cluster extra: pip install 'insect-gait[cluster]' "
                f"({exc})"
            ) from exc
        self._cluster: Any = None
        if address:
            self._client: Any = Client(address)
            self.workers = max(1, sum(self._client.nthreads().values()))
        else:
            self.workers = max(1, workers or os.cpu_count() or 1)
            self._cluster = LocalCluster(
                n_workers=self.workers,
                threads_per_worker=1,
                processes=processes,
                dashboard_address=None,
            )
            self._client = Client(self._cluster)

    def imap(self, fn: Executor, chunks: Sequence[list[Task]]) -> ChunkResults:
        from distributed import as_completed

        if not chunks:
            return
        futures = self._client.map(fn, list(chunks), pure=False)
        index = {f.key: k for k, f in enumerate(futures)}
        try:
            for fut in as_completed(futures):
                yield chunks[index[fut.key]], fut.result()
        finally:
            self._client.cancel(futures)

    def close(self) -> None:
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()


def get_backend(
    name: str, workers: int | None = None, address: str | None = None, processes: bool = True
) -> Backend:
    """The backend called `name`; BackendUnavailable says why when it cannot run."""
    if name == "ray":
        raise BackendUnavailable(RAY_UNSUPPORTED)
    if address and name != "dask":
        raise BackendUnavailable("--address needs --backend dask")
    if name == "local":
        return LocalBackend(workers)
    if name == "inline":
        return InlineBackend()
    if name == "dask":
        return DaskBackend(address, workers, processes)
    raise BackendUnavailable(f"unknown backend {name!r}; choose from {BACKENDS}")


@dataclass
class RunStats:
    """What one `run_tasks` call did: tasks asked for (deduplicated), computed, from cache."""

    tasks: int = 0
    computed: int = 0
    cached: int = 0
    compute_s: float = 0.0  # summed single-core compute time of every result used

    def add(self, other: RunStats) -> None:
        """Count `other`'s tasks in these (a job or a study of several `run_tasks` calls)."""
        self.tasks += other.tasks
        self.computed += other.computed
        self.cached += other.cached
        self.compute_s += other.compute_s


def run_tasks(
    tasks: Sequence[Task],
    cache: ResultCache,
    backend: Backend,
    chunk_size: int = 8,
    progress: bool | str = True,
    executor: Executor = execute_chunk,
    on_progress: Callable[[float], None] | None = None,
) -> tuple[dict[str, dict[str, Any]], RunStats]:
    """Results of every task by key: from the cache, or computed on `backend` and cached;
    `on_progress`, if given, hears the share of tasks done (0..1) after every chunk (a job's
    progress, where `progress` draws a bar on a terminal, labelled with it if it is a str,
    else "reproduce"). A cache with a limit is trimmed after new results were stored: the
    least recently used results go, the ones this call used are the newest."""
    from tqdm import tqdm

    unique = list({t.key: t for t in tasks}.values())
    results: dict[str, dict[str, Any]] = {}
    pending: list[Task] = []
    for t in unique:
        hit = cache.get(t)
        if hit is None:
            pending.append(t)
        else:
            results[t.key] = hit
    stats = RunStats(tasks=len(unique), cached=len(unique) - len(pending))
    chunks = make_chunks(pending, chunk_size, backend.workers)
    label = progress if isinstance(progress, str) else "reproduce"
    with tqdm(total=len(unique), initial=stats.cached, unit="task", desc=label,
              disable=not progress, dynamic_ncols=True) as bar:  # fmt: skip
        for chunk, outs in backend.imap(executor, chunks):
            if len(outs) != len(chunk):
                raise RuntimeError(f"a chunk of {len(chunk)} tasks returned {len(outs)} results")
            for t, r in zip(chunk, outs, strict=True):
                r = json.loads(json.dumps(r, allow_nan=False))  # as a cache hit would read
                cache.put(t, r)
                results[t.key] = r
            stats.computed += len(chunk)
            bar.update(len(chunk))
            if on_progress is not None:
                on_progress((stats.cached + stats.computed) / max(1, len(unique)))
    stats.compute_s = sum(float(r.get("compute_s", 0.0)) for r in results.values())
    if stats.computed:
        cache.maybe_trim()  # within its limit again, the results just used kept (the newest)
    return results, stats

"""Worker processes and the supervisor thread that feeds them.

Why not huey (see docs/API.md for the long form): its SQLite storage deletes a task when a
consumer takes it, so a `kill -9` loses every running task, and `revoke` only skips tasks not yet
started, so cancel could not stop a running simulation. Both would need this module anyway, and
two queues (huey's and the job table) could disagree after a crash. Here the job table is the
queue, and the supervisor owns the worker processes, so it can kill the one running a cancelled
job.

Shape: the supervisor (a thread in the API process, doing no simulation) claims the oldest queued
job for each idle worker and sends the worker its id over a pipe. The worker reads the spec,
simulates, writes progress and the result to SQLite itself (fenced by the claim) and answers
"finished". Cancel = the API marks the job cancelled; the supervisor sees a busy worker's job
cancelled, SIGKILLs that worker and starts a fresh one (on the Dask path the worker's client dies
with it, and the scheduler forgets a dead client's futures: the job's chunks not yet started
never run, a chunk already running finishes on its cluster worker and is dropped). Each job's
simulations go through the shared result cache (`server.kinds.compute`), so a job killed mid-way
and run again starts from the chunks it had finished. A worker that dies on its own (segfault,
out of memory) fails only its own job. Workers die with the API process (PR_SET_PDEATHSIG plus a
parent watchdog), so after `kill -9` no orphan keeps simulating.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing as mp
import os
import signal
import socket
import sys
import threading
import time
import traceback
from dataclasses import dataclass, field
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from pathlib import Path
from typing import Any

from server.jobs import Claim, JobStore, Simulations
from server.kinds.compute import Compute, ComputeSettings
from server.settings import Settings
from server.status import JobStatus

log = logging.getLogger("insect_gait.server.workers")

PROGRESS_EVERY_S = 0.25
RESPAWN_BACKOFF_S = 1.0


# ---- inside a worker process --------------------------------------------------------------


def _die_with_parent(parent_pid: int) -> None:
    """Make sure a worker never outlives the API process that owns its job."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
        except Exception:  # the watchdog below still covers it
            pass
    if os.getppid() != parent_pid:  # the parent died before prctl took effect
        os._exit(1)

    def watchdog() -> None:
        while True:
            time.sleep(0.5)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watchdog, name="parent-watchdog", daemon=True).start()


def lower_priority(niceness: int) -> int:
    """Run this process at OS niceness at least `niceness` (0..19), so that simulations yield
    the CPU to the live viewer and the API on a shared machine. Only ever lowers the
    priority (raising it needs privileges). Returns the niceness now in effect.

    With the kernel's autogroup scheduling on (the Linux default), niceness only ranks
    processes inside one session; between sessions the CPU is shared equally, so a niced worker
    in the API's session still took half the machine from a viewer started in another
    (measured: viewer 0.38-0.58x with one worker at nice 10 or 19). A worker therefore starts
    its own session and sets that session's autogroup niceness too.
    """
    # the session first, the process's niceness last: whoever sees the niceness in effect
    # sees the session's too
    if niceness > 0 and Path("/proc/self/autogroup").exists():
        with contextlib.suppress(OSError):
            os.setsid()  # its own autogroup (PR_SET_PDEATHSIG still ties it to the API)
            Path("/proc/self/autogroup").write_text(str(min(19, niceness)))
    current = os.getpriority(os.PRIO_PROCESS, 0)
    if niceness > current:
        with contextlib.suppress(OSError):
            os.setpriority(os.PRIO_PROCESS, 0, min(19, niceness))
    return os.getpriority(os.PRIO_PROCESS, 0)


def worker_main(
    conn: Connection,
    db_path: str,
    nthread: int,
    parent_pid: int,
    niceness: int = 0,
    where: ComputeSettings | None = None,
) -> None:
    """Loop: receive (job_id, attempt), run it, answer. Exits on None or a closed pipe.
    `where`: the result cache and the backend every job's simulations go through (default:
    the installation's cache, computed here)."""
    _die_with_parent(parent_pid)
    lower_priority(niceness)
    # Ctrl-C and `kill 0` (make run) signal the whole group; the API process decides what
    # happens to a running job (re-queue on shutdown) and SIGKILLs workers itself, so a
    # worker must not die first and have its job counted as crashed.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    from server.errors import exception_message, sanitize
    from server.kinds import JOB_SPEC_ADAPTER, JobFailed, execute, open_compute

    where = where or ComputeSettings(cache_dir=Settings().cache_dir)

    with contextlib.suppress(Exception):
        # warm the engine (MuJoCo, numba) before the first job arrives; `import sim_core`
        # alone is lazy and loads neither
        from sim_core import simulate_batch  # noqa: F401

    store = JobStore(db_path)
    conn.send(("ready", os.getpid()))
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            return
        if msg is None:
            return
        claim = Claim(*msg)
        last = 0.0

        def progress(fraction: float, claim: Claim = claim) -> None:
            nonlocal last
            now = time.monotonic()
            if now - last >= PROGRESS_EVERY_S:
                last = now
                store.set_progress(claim, fraction)

        compute: Compute | None = None
        try:
            raw = store.spec_of(claim.job_id)
            if raw is None:
                raise JobFailed("the job disappeared from the database")
            job = JOB_SPEC_ADAPTER.validate_python(raw)
            compute = open_compute(where, progress, nthread)
            result = execute(job, compute)
            if not store.finish_done(claim, result, compute.counts()):
                log.info("job %s finished but was cancelled or re-queued meanwhile", claim.job_id)
        except JobFailed as exc:
            store.finish_failed(claim, sanitize(str(exc)), _counts(compute))
        except Exception as exc:
            # the client gets the type and message, never paths or a traceback; the operator
            # gets the traceback in the server's log
            print(f"job {claim.job_id} failed:\n{traceback.format_exc()}", file=sys.stderr)
            store.finish_failed(claim, exception_message(exc), _counts(compute))
        finally:
            if compute is not None:
                with contextlib.suppress(Exception):  # a cluster gone already: nothing to close
                    compute.backend.close()
        try:
            conn.send(("finished", claim.job_id))
        except (BrokenPipeError, OSError):
            return


def _counts(compute: Compute | None) -> Simulations | None:
    """What a job simulated before it failed (None: it never reached its simulations)."""
    return None if compute is None else compute.counts()


# ---- inside the API process ---------------------------------------------------------------


@dataclass
class _Worker:
    proc: BaseProcess
    conn: Connection
    started: float
    claim: Claim | None = None
    ready: bool = False
    pid: int | None = None


@dataclass
class PoolStats:
    configured: int
    alive: int
    busy: int


@dataclass
class WorkerPool:
    """Owns N worker processes and the supervisor thread; start() and stop() from lifespan."""

    store: JobStore
    db_path: Path
    size: int
    nthread: int
    niceness: int = 0
    where: ComputeSettings | None = None  # the jobs' result cache and backend
    _workers: list[_Worker] = field(default_factory=list)
    _thread: threading.Thread | None = None
    _stop: threading.Event = field(default_factory=threading.Event)
    _wake_r: socket.socket | None = None
    _wake_w: socket.socket | None = None
    _ctx: Any = field(default_factory=lambda: mp.get_context("spawn"))
    _respawn_at: float = 0.0

    def start(self) -> None:
        # the first workers start here, in the caller's (main) thread, where a spawn can hide
        # an early Ctrl-C from the child (`_spawn`); the supervisor thread only respawns
        self._workers = [self._spawn() for _ in range(self.size)]
        self._wake_r, self._wake_w = socket.socketpair()
        self._wake_r.setblocking(False)
        self._wake_w.setblocking(False)
        self._thread = threading.Thread(target=self._run, name="job-supervisor", daemon=True)
        self._thread.start()

    def wake(self) -> None:
        """Tell the supervisor to look at the queue now (a job arrived or was cancelled)."""
        if self._wake_w is not None:
            with contextlib.suppress(BlockingIOError, OSError):
                self._wake_w.send(b"x")

    def stats(self) -> PoolStats:
        workers = list(self._workers)
        alive = sum(1 for w in workers if w.proc.is_alive())
        busy = sum(1 for w in workers if w.claim is not None)
        return PoolStats(configured=self.size, alive=alive, busy=busy)

    def stop(self, timeout: float = 15.0) -> None:
        """Clean shutdown: running jobs go back to the queue; every worker process ends.

        The supervisor thread ends the workers itself: PR_SET_PDEATHSIG fires when the thread
        that started a worker exits, so it must be the last to touch them.
        """
        self._stop.set()
        self.wake()
        if self._thread is not None:
            self._thread.join(timeout)
        for s in (self._wake_r, self._wake_w):
            if s is not None:
                s.close()

    # ---- supervisor thread ----------------------------------------------------------------

    def _spawn(self) -> _Worker:
        parent, child = self._ctx.Pipe(duplex=True)
        proc = self._ctx.Process(
            target=worker_main,
            args=(child, str(self.db_path), self.nthread, os.getpid(), self.niceness, self.where),
            name="insect-gait-worker",
            daemon=True,
        )
        # A Ctrl-C while the child is still importing (spawn re-imports the main script
        # before worker_main runs) would print its KeyboardInterrupt traceback. The signal
        # mask does not survive multiprocessing's fork_exec (measured: SigBlk 0 in the child),
        # but an ignored disposition survives exec, and Python then installs no SIGINT
        # handler of its own: so the child is started with SIGINT ignored. Here SIGINT is
        # blocked meanwhile, so that a Ctrl-C in that instant stays pending for this process
        # (Linux keeps a blocked signal pending even while ignored) and arrives once the
        # handler is back. Python changes dispositions only in the main thread: the pool's
        # first workers start there (`start`, from the app's lifespan); a respawn after a
        # crash starts from the supervisor thread and keeps the short window.
        main = threading.current_thread() is threading.main_thread()
        old_mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        old_handler = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
        try:
            proc.start()
        finally:
            if main:
                signal.signal(signal.SIGINT, old_handler)
            signal.pthread_sigmask(signal.SIG_SETMASK, old_mask)
        child.close()
        return _Worker(proc=proc, conn=parent, started=time.monotonic())

    def _end_worker(self, w: _Worker, requeue: bool) -> None:
        if w.conn.closed:
            return
        if w.claim is not None and requeue:
            self.store.requeue_on_shutdown(w.claim)
        if w.proc.is_alive():
            if w.claim is None and w.ready:
                with contextlib.suppress(OSError):
                    w.conn.send(None)
                w.proc.join(1.0)
            if w.proc.is_alive():
                w.proc.kill()
        w.proc.join(2.0)
        w.conn.close()

    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                self._step()
        except Exception:  # keep the API answering; /healthz shows the workers as gone
            log.exception("job supervisor crashed")
        finally:
            for w in self._workers:
                self._end_worker(w, requeue=True)

    def _step(self) -> None:
        self._reap_dead()
        self._kill_cancelled()
        self._assign()
        waitables: list[Any] = [w.conn for w in self._workers if not w.conn.closed]
        if self._wake_r is not None:
            waitables.append(self._wake_r)
        for ready in wait(waitables, timeout=0.2):
            if ready is self._wake_r:
                with contextlib.suppress(BlockingIOError, OSError):
                    self._wake_r.recv(4096)
                continue
            w = next(w for w in self._workers if w.conn is ready)
            try:
                kind, payload = w.conn.recv()
            except (EOFError, OSError):
                continue  # it died; _reap_dead handles it
            if kind == "ready":
                w.ready, w.pid = True, int(payload)
            elif kind == "finished":
                w.claim = None

    def _reap_dead(self) -> None:
        for i, w in enumerate(self._workers):
            if w.proc.is_alive():
                continue
            code = w.proc.exitcode
            how = f"signal {-code}" if code is not None and code < 0 else f"exit code {code}"
            if w.claim is not None:
                what = self.store.worker_died(
                    w.claim,
                    f"the worker process died ({how}) while running this job: killed from "
                    "outside, out of memory, or a crash; other jobs are not affected",
                )
                log.warning("worker %s died (%s) running job %s: %s", w.pid, how,
                            w.claim.job_id, what)  # fmt: skip
            w.conn.close()
            if time.monotonic() - w.started < 2.0:
                # dying at start-up again and again must not become a fork loop
                self._respawn_at = time.monotonic() + RESPAWN_BACKOFF_S
            if time.monotonic() >= self._respawn_at:
                self._workers[i] = self._spawn()
            else:
                w.claim = None

    def _kill_cancelled(self) -> None:
        busy = {w.claim.job_id: w for w in self._workers if w.claim is not None}
        if not busy:
            return
        statuses = self.store.status_of(list(busy))
        for job_id, w in busy.items():
            status = statuses.get(job_id)
            # done/failed: the worker wrote it and its "finished" is on the way; leave it be
            if status is not None and status is not JobStatus.CANCELLED:
                continue
            log.info("job %s is %s: stopping worker %s", job_id, status or "missing", w.pid)
            w.proc.kill()
            w.proc.join(2.0)
            w.conn.close()
            self._workers[self._workers.index(w)] = self._spawn()

    def _assign(self) -> None:
        for w in self._workers:
            if w.claim is not None or not w.ready or not w.proc.is_alive():
                continue
            claim = self.store.claim_next()
            if claim is None:
                return
            try:
                w.conn.send((claim.job_id, claim.attempt))
            except OSError:
                self.store.requeue_on_shutdown(claim)
                continue
            w.claim = claim

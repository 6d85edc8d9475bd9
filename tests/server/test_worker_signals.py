"""A Ctrl-C in the first seconds of `make run` must not print a worker's traceback.

Spawned workers re-import the main script before `worker_main` can ignore SIGINT; the pool
therefore starts them with SIGINT already ignored (a disposition survives exec, a signal mask
does not). Read from the kernel: /proc/PID/status lists the ignored signals.
"""

from __future__ import annotations

import os
import signal
import sys
import time
from pathlib import Path

import pytest

from server.jobs import JobStore
from server.workers import WorkerPool

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")


def _ignored(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("SigIgn:"):
            return int(line.split()[1], 16)
    raise AssertionError("no SigIgn line")


def test_a_worker_ignores_ctrl_c_from_its_first_instruction(tmp_path: Path) -> None:
    db = tmp_path / "jobs.db"
    store = JobStore(db)
    store.init()
    pool = WorkerPool(store=store, db_path=db, size=1, nthread=1)
    before = signal.getsignal(signal.SIGINT)
    pool.start()
    try:
        assert signal.getsignal(signal.SIGINT) is before  # the API keeps its own handler
        (worker,) = pool._workers  # started by start() itself, in this (main) thread
        pid = worker.proc.pid
        assert pid is not None
        assert _ignored(pid) & (1 << (signal.SIGINT - 1)), "SIGINT not ignored at exec"
        os.kill(pid, signal.SIGINT)  # while it is still importing
        time.sleep(1.0)
        assert worker.proc.is_alive(), f"the worker died of Ctrl-C: {worker.proc.exitcode}"
    finally:
        pool.stop()

"""`make run` stops cleanly on Ctrl-C: both servers go, and nothing says "Error" or "Segmentation".

The test runs the Makefile's own recipe (test ports, a temporary database) in a process group of
its own and sends SIGINT to the whole group, as a terminal does on Ctrl-C. GNU make itself then
re-raises the interrupt after its recipe has finished (that is how make reports an interrupted
run: silently, with the signal as its status), so make's status is either 0 or "killed by
SIGINT"; what must never appear is make's error line for the recipe ("make: *** [...] Error" /
"Segmentation fault"), which is what the old `trap 'kill 0'` recipe printed every time.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


def _free_ports(n: int) -> list[int]:
    """n distinct free ports (held open together, so the OS cannot hand out one twice)."""
    socks = [socket.socket() for _ in range(n)]
    try:
        for s in socks:
            s.bind(("127.0.0.1", 0))
        return [int(s.getsockname()[1]) for s in socks]
    finally:
        for s in socks:
            s.close()


def _listening(port: int) -> bool:
    """A whole HTTP request, not a bare connect: a connection closed before its request line
    makes the viewer's websocket server log a handshake traceback (seen under load), which
    this probe must not cause."""
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=2) as r:
            return bool(r.status)
    except urllib.error.HTTPError:
        return True  # it answered
    except (OSError, ValueError):
        return False


@pytest.mark.skipif(shutil.which("make") is None, reason="needs GNU make")
@pytest.mark.skipif(not (BIN / "insect-gait").exists(), reason="needs the insect-gait script")
def test_ctrl_c_stops_make_run_quietly(tmp_path: Path) -> None:
    api, viewer = _free_ports(2)
    env = dict(
        os.environ,
        INSECT_GAIT_DB_PATH=str(tmp_path / "jobs.sqlite3"),
        # no worker processes: this tests the recipe; a worker still importing when Ctrl-C
        # arrives prints a KeyboardInterrupt traceback of its own (server/, reported)
        INSECT_GAIT_WORKERS="0",
    )
    # -o: do not rebuild the virtual environment; BIN: the one running this test
    cmd = ["make", "--no-print-directory", "-o", ".venv/.installed", "run", f"BIN={BIN}"]
    proc = subprocess.Popen(
        [*cmd, f"API_PORT={api}", f"VIEWER_PORT={viewer}"],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,  # its own process group, like a terminal's foreground job
    )
    try:
        deadline = time.monotonic() + 120
        while not (_listening(api) and _listening(viewer)):
            assert proc.poll() is None, f"make run exited early:\n{proc.stdout.read()}"  # type: ignore[union-attr]
            assert time.monotonic() < deadline, "servers did not start"
            time.sleep(0.5)
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C
        out, _ = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    bad = [
        line
        for line in out.splitlines()
        if any(word in line for word in ("Error", "Segmentation", "make: ***", "Traceback"))
    ]
    assert bad == [], out
    assert proc.returncode in (0, -signal.SIGINT), (proc.returncode, out)
    assert not _listening(api) and not _listening(viewer), "a server outlived make run"

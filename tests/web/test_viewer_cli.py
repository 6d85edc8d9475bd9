"""`insect-gait viewer` at its edges: a bad or busy port is refused in one line, exit 2.

Before: `--port -5` printed an OverflowError traceback from a thread and never exited, and a
busy port made viser move to the next one while `make run` had printed the asked one.
"""

from __future__ import annotations

import socket
import subprocess
import sys
from pathlib import Path

import pytest

EXE = Path(sys.executable).parent / "insect-gait"
REPO = Path(__file__).resolve().parents[2]


def _viewer(*args: str, timeout: float = 90) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(EXE), "viewer", *args], cwd=REPO, capture_output=True,
                          text=True, timeout=timeout)  # fmt: skip


@pytest.mark.parametrize("port", ["-5", "0", "65536", "99999", "x"])
def test_a_bad_port_is_refused_at_once(port: str) -> None:
    out = _viewer("--port", port, timeout=30)
    assert out.returncode == 2
    assert "is not a port number (1..65535)" in out.stderr
    assert "Traceback" not in out.stderr


@pytest.mark.parametrize("fps", ["-1", "x", "nan"])
def test_a_bad_frame_cap_is_refused_at_once(fps: str) -> None:
    out = _viewer("--software-fps", fps, timeout=30)
    assert out.returncode == 2
    assert "--software-fps" in out.stderr and "frames a second" in out.stderr
    assert "Traceback" not in out.stderr


@pytest.mark.parametrize(
    ("flags", "words"),
    [(["--param", "kp_lifts=1"], "--param: unknown model parameter 'kp_lifts'"),
     (["--setting", "stiff"], "--setting: no model setting 'stiff'")],
)  # fmt: skip
def test_a_bad_model_parameter_is_refused_at_once(flags: list[str], words: str) -> None:
    """The viewer takes `insect-gait run`'s model flags, parsed and refused alike."""
    out = _viewer(*flags, timeout=30)
    assert out.returncode == 2 and words in out.stderr, out.stderr
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr


def test_a_busy_port_is_refused_not_silently_moved() -> None:
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        out = _viewer("--host", "127.0.0.1", "--port", str(port))
    assert out.returncode == 2, out.stdout + out.stderr
    assert f"port {port} on 127.0.0.1 is already in use" in out.stderr
    assert f":{port + 1}" not in out.stdout  # no URL of somebody else's port
    assert "Traceback" not in out.stderr

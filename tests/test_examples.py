"""Every script in examples/ runs, with tiny sizes: the README's introduction cannot rot.

The REST client runs against a real server (`python -m server`, a worker process, SQLite).
The `slow` tests run every example and the notebook with their own defaults, as a new user
would, and time them (issue 55: each within a minute on a 2-core host).
"""

import json
import os
import socket
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.server.api_harness import Server, make_server

__all__ = ["make_server"]  # the fixture, re-exported for pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TINY = {
    "01_walk_once.py": ["--duration-s", "0.6"],
    "02_return_map.py": ["--starts", "2.0", "3.0", "--duration-s", "1.0", "--out", "{tmp}/map.png"],
    "03_live_beta_ramp.py": ["--settle-s", "0.2", "--ramp-s", "0.4"],
    "04_batch_sweep.py": ["--betas", "0.62", "0.70", "--starts", "2", "--duration-s", "0.6"],
}


# what a new user may wait for an example with its defaults on a 2-core host (issue 55)
DEFAULTS_WALL_S = 60.0


def _run(script: str, args: list[str], tmp: Path) -> str:
    cmd = [sys.executable, str(EXAMPLES / script), *(a.format(tmp=tmp) for a in args)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=tmp)
    assert done.returncode == 0, f"{script} failed:\n{done.stdout}\n{done.stderr}"
    return done.stdout


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def test_every_example_is_covered() -> None:
    scripts = {p.name for p in EXAMPLES.glob("*.py")}
    assert scripts == {*TINY, "05_rest_client.py"}
    for p in EXAMPLES.glob("*.py"):
        assert len(p.read_text().splitlines()) <= 45, f"{p.name} is no longer short"


@pytest.mark.parametrize("script", sorted(TINY))
def test_example_runs(script: str, tmp_path: Path) -> None:
    out = _run(script, TINY[script], tmp_path)
    assert out.strip()
    if script == "02_return_map.py":
        assert (tmp_path / "map.png").stat().st_size > 0


def test_the_tour_notebook_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """examples/06_tour.ipynb, executed cell by cell in a real Jupyter kernel (tiny sizes):
    a walk, a return map, the drift surface and a REST job on a server it starts itself."""
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    monkeypatch.setenv("INSECT_GAIT_TOUR_QUICK", "1")
    monkeypatch.setenv("PYTHONPATH", str(EXAMPLES.parent))
    nb = nbformat.read(EXAMPLES / "06_tour.ipynb", as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    client.execute()
    text = "\n".join(
        o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.outputs
    )
    assert "gait " in text and "Delta31" in text and "zero at Delta31" in text
    assert "done d31_init," in text  # the REST job's CSV
    images = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs
              if "image/png" in o.get("data", {})]  # fmt: skip
    assert len(images) == 3  # the walk, the return map, the surface


def test_rest_client_example(make_server: Callable[..., Server], tmp_path: Path) -> None:
    server = make_server()
    out = _run("05_rest_client.py", ["--url", server.url, "--duration-s", "0.3"], tmp_path)
    lines = out.strip().splitlines()
    header = next(k for k, line in enumerate(lines) if line.startswith("d31_init,"))
    assert "queued job" in lines[0] and "d31_final" in lines[header]
    assert len(lines) - header - 1 == 2  # one CSV row per start


def test_rest_client_without_a_service_says_what_to_do(tmp_path: Path) -> None:
    """No API at the URL: one line that names `make run`, no traceback, a failing exit code."""
    url = f"http://127.0.0.1:{_free_port()}"
    for target in (url, "not-a-url"):
        cmd = [sys.executable, str(EXAMPLES / "05_rest_client.py"), "--url", target]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=60, cwd=tmp_path)
        assert done.returncode != 0 and done.stdout == ""
        assert done.stderr.count("\n") == 1 and "Traceback" not in done.stderr, done.stderr
        assert "make run" in done.stderr and "insect-gait api" in done.stderr


def test_the_stored_notebook_carries_no_outputs() -> None:
    """Executed, the tour holds three PNGs and a progress bar's hundred updates (~130 kB): it
    is stored without them, so that the repository and its diffs stay small."""
    path = EXAMPLES / "06_tour.ipynb"
    nb = json.loads(path.read_text())
    code = [c for c in nb["cells"] if c["cell_type"] == "code"]
    assert code and all(c["outputs"] == [] and c["execution_count"] is None for c in code)
    assert path.stat().st_size < 20_000


@pytest.mark.slow
@pytest.mark.parametrize("script", sorted([*TINY]))
def test_example_with_its_defaults_finishes_in_a_minute(script: str, tmp_path: Path) -> None:
    """As a new user runs it: no arguments. It prints while it works (a progress bar on
    stderr or lines on stdout), finds what its title says, and is done within a minute."""
    t0 = time.perf_counter()
    cmd = [sys.executable, str(EXAMPLES / script)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=tmp_path)
    wall = time.perf_counter() - t0
    assert done.returncode == 0, done.stdout + done.stderr
    assert wall < DEFAULTS_WALL_S, f"{script} took {wall:.0f} s"
    out = done.stdout
    if script == "01_walk_once.py":  # a settled walk names its gait
        assert "metachronal (settled)" in out, out
    if script == "02_return_map.py":  # both gaits at beta 0.62, said, and the figure
        found = next(line for line in out.splitlines() if line.startswith("found:"))
        assert "tripod" in found and "metachronal" in found, out
        assert (tmp_path / "return_map.png").stat().st_size > 0
    if script == "03_live_beta_ramp.py":
        assert out.count("beta ") >= 40, out  # a line per ramp step, as it goes
    if script == "04_batch_sweep.py" and "~" in out:  # an unsettled end is explained
        assert "~ not settled by the project's rule" in out, out
    if script != "03_live_beta_ramp.py":
        assert "sim s" in done.stderr  # the progress bar


@pytest.mark.slow
def test_the_tour_notebook_with_its_defaults_finishes_in_a_minute(tmp_path: Path) -> None:
    """The tour as its README line runs it headless (`jupyter execute`), full sizes."""
    jupyter = Path(sys.executable).with_name("jupyter")
    nb = tmp_path / "06_tour.ipynb"
    nb.write_text((EXAMPLES / "06_tour.ipynb").read_text())
    env = {k: v for k, v in os.environ.items() if k != "INSECT_GAIT_TOUR_QUICK"}
    env["PYTHONPATH"] = str(EXAMPLES.parent)
    t0 = time.perf_counter()
    cmd = [str(jupyter), "execute", "--kernel_name=python3", "--output=ran", str(nb)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    wall = time.perf_counter() - t0
    assert done.returncode == 0, done.stderr
    assert wall < DEFAULTS_WALL_S, f"the tour took {wall:.0f} s"
    ran = json.loads((tmp_path / "ran.ipynb").read_text())
    text = "".join("".join(o.get("text", "")) for c in ran["cells"] if c["cell_type"] == "code"
                   for o in c["outputs"])  # fmt: skip
    assert "gait tripod" in text and "zero at Delta31" in text and "done d31_init," in text

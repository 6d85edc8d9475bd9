"""Every script in examples/ runs, with tiny sizes: the README's introduction cannot rot.

The REST client runs against a real server (`python -m server`, a worker process, SQLite).
"""

import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.server.api_harness import Server, make_server

__all__ = ["make_server"]  # the fixture, re-exported for pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TINY = {
    "01_walk_once.py": ["--duration-s", "0.6"],
    "02_return_map.py": ["--starts", "3", "--duration-s", "1.0", "--out", "{tmp}/map.png"],
    "03_live_beta_ramp.py": ["--settle-s", "0.2", "--ramp-s", "0.4"],
    "04_batch_sweep.py": ["--betas", "0.62", "0.70", "--starts", "2", "--duration-s", "0.6"],
}


def _run(script: str, args: list[str], tmp: Path) -> str:
    cmd = [sys.executable, str(EXAMPLES / script), *(a.format(tmp=tmp) for a in args)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=tmp)
    assert done.returncode == 0, f"{script} failed:\n{done.stdout}\n{done.stderr}"
    return done.stdout


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

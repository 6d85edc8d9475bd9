"""Where the viewer finds files: light, so that `insect-gait --help` loads no viser.

One constant decides where the finder's results are looked for (`RESULTS_DIR`): the folder
`insect-gait reproduce` and `insect-gait atlas` write by default, the repository's
docs/figures, when the viewer runs from a checkout; otherwise ./docs/figures of the directory
it was started in. `INSECT_GAIT_RESULTS` overrides it, and `--bifurcation PATH` names the
bifurcation file itself (the atlas files are read from the same folder).
"""

from __future__ import annotations

import os
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
RESULTS_ENV = "INSECT_GAIT_RESULTS"
DEFAULT_API_URL = "http://127.0.0.1:8000"  # `make run` starts the API there
# the file names the core's writers use (sim_core.paper.reproduce.VIEWER_BIFURCATION and
# sim_core.paper.atlas: atlas_<axis>.json)
BIFURCATION_FILE = "bifurcation.json"
ATLAS_AXES = ("mass", "slope")


def _results_dir() -> Path:
    env = os.environ.get(RESULTS_ENV)
    if env:
        return Path(env)
    repo = REPO_ROOT / "docs" / "figures"
    return repo if repo.is_dir() else Path("docs") / "figures"


RESULTS_DIR = _results_dir()
DEFAULT_BIFURCATION = RESULTS_DIR / BIFURCATION_FILE


def atlas_path(folder: Path, axis: str) -> Path:
    """atlas_mass.json / atlas_slope.json next to the bifurcation file."""
    if axis not in ATLAS_AXES:
        raise ValueError(f"unknown atlas axis {axis!r}; choose from {ATLAS_AXES}")
    return folder / f"atlas_{axis}.json"

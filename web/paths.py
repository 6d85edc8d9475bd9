"""Where the viewer finds files: light, so that `insect-gait --help` loads no viser."""

from __future__ import annotations

from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
DEFAULT_BIFURCATION = REPO_ROOT / "docs" / "figures" / "bifurcation.json"

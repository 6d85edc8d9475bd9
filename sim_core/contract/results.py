"""Where the project's results live: one folder, named once, that the writers fill and the
viewer reads.

`insect-gait reproduce`, `atlas`, `numerics`, `sensitivity` and the studies' figures write
into `RESULTS_DIR` by default; the viewer reads the finder's output (`BIFURCATION_FILE`, a
`FinderOutput`) and the atlases (`atlas_file`, an `AtlasOutput` each) from the same folder, so
a reproduce or an atlas run shows up in the viewer without naming a path anywhere.

The folder is the checkout's docs/figures (the README and docs/REPRODUCTION.md show what is
there) when the package runs from a checkout, else ./docs/figures of the working directory;
`INSECT_GAIT_RESULTS` overrides both (a container mounts its results there). Light on
purpose (os and pathlib only), so the CLI's parsers name their default folder without
loading anything heavy.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Literal, get_args

RESULTS_ENV = "INSECT_GAIT_RESULTS"
# the checkout this package sits in (sim_core/contract/results.py -> the repository root)
_CHECKOUT = Path(__file__).resolve().parents[2]
# the finder's output over Fig. 8's betas (`insect-gait finder`); the viewer validates it
BIFURCATION_FILE = "bifurcation.json"
# the drift surface over Fig. 8's betas (`insect-gait reproduce`); a `DriftSurface`
SURFACE_FILE = "surface.json"
SURFACE_PENALTY_FILE = "surface_penalty.json"  # the mechanism's surface on the paper's ground
# the gait atlas's second axis beside beta (`sim_core.paper.atlas`): one file each
AtlasAxis = Literal["mass", "slope"]
ATLAS_AXES: tuple[str, ...] = get_args(AtlasAxis)


def results_dir() -> Path:
    """The results folder now: $INSECT_GAIT_RESULTS, the checkout's docs/figures, or
    ./docs/figures."""
    env = os.environ.get(RESULTS_ENV)
    if env:
        return Path(env)
    repo = _CHECKOUT / "docs" / "figures"
    return repo if repo.is_dir() else Path("docs") / "figures"


RESULTS_DIR = results_dir()


def atlas_file(folder: Path, axis: str) -> Path:
    """atlas_mass.json / atlas_slope.json in `folder`: the finder's atlas (`write_atlas`,
    `python -m lab finder-atlas`)."""
    if axis not in ATLAS_AXES:
        raise ValueError(f"unknown atlas axis {axis!r}; choose from {ATLAS_AXES}")
    return folder / f"atlas_{axis}.json"


def surface_atlas_file(folder: Path, axis: str, ground: str) -> Path:
    """surface_atlas_<axis>_<ground>.json in `folder`: what `insect-gait atlas` writes and the
    viewer's atlas panel reads (a `SurfaceAtlas`)."""
    if axis not in ATLAS_AXES:
        raise ValueError(f"unknown atlas axis {axis!r}; choose from {ATLAS_AXES}")
    return folder / f"surface_atlas_{axis}_{ground}.json"

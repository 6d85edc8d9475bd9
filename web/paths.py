"""Where the viewer finds things: light, so that `insect-gait --help` loads no viser.

The results folder (the finder's bifurcation file, the atlases) is the core's one results
place (`sim_core.contract.results`, through the contract): what `insect-gait reproduce`,
`finder` and `atlas` write by default, `INSECT_GAIT_RESULTS` overriding
it; `--bifurcation PATH` names the bifurcation file itself (the atlas files and, unless
`--surface PATH` names another, the drift surface are read from the same folder).
"""

from __future__ import annotations

from sim_core.contract import BIFURCATION_FILE, RESULTS_DIR, SURFACE_FILE

DEFAULT_API_URL = "http://127.0.0.1:8000"  # `make run` starts the API there
DEFAULT_BIFURCATION = RESULTS_DIR / BIFURCATION_FILE
DEFAULT_SURFACE = DEFAULT_BIFURCATION.parent / SURFACE_FILE

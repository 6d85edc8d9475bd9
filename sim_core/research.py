"""The lab's face: what a study needs beyond the product's API and the contract.

The studies in lab/ (`python -m lab`, not installed) are a client of the core like the edges;
the names they need and the edges do not (the model's insides, cached runs on a backend, the
reproduction's protocols, what the paper states, readings of a run) are public here, apart
from the product's (`sim_core`) and the contract's (`sim_core.contract`), so that those two
faces hold what server/ and web/ use and no more.

Listed once, as the imports of research.pyi (which type checkers read); each name loads its
module on first use (PEP 562), as the package root's do, so `import sim_core.research` costs
no MuJoCo or numba import. Not `lazy_loader.attach_stub`, which the root uses: it reads a
stub's imports as the submodules of the name it is given and caches each loaded name there;
given `sim_core` (these are the package's modules: `from .paper.atlas import ...` in
research.pyi is sim_core.paper.atlas), it would cache the lab's names on the package root.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path


def _homes() -> dict[str, str]:
    """Each public name -> the module it is defined in, from research.pyi's imports."""
    stub = ast.parse(Path(__file__).with_suffix(".pyi").read_text())
    package = __name__.rpartition(".")[0]
    return {
        alias.name: f"{package}.{node.module}"
        for node in stub.body
        if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module
        for alias in node.names
    }


_HOMES = _homes()
__all__ = sorted(_HOMES)


def __getattr__(name: str) -> object:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(home), name)
    globals()[name] = value  # later uses bypass this function
    return value


def __dir__() -> list[str]:
    return list(__all__)

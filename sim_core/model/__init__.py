"""Everything that can change a simulated number (its version: `version.PHYSICS_VERSION`).

numba's on-disk cache (`cache=True` on the kernels) notices an edit only in the file that
defines a function, not in a function it calls from another file: after an edit of
`legs.swing_point`, `controller.plan_block` kept running the old swing curve from its cache
(a new option once had no effect until the cache was cleared). So the kernels
are cached in a folder named after a hash of this package's sources, set here before any of
them is compiled: an edit anywhere in the package starts a fresh cache.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

_BASE = "INSECT_GAIT_KERNEL_CACHE"  # where the hashed folders live


def source_hash(folder: Path) -> str:
    """sha256 (16 hex) over every Python source in `folder`: numba's compiled kernels are a
    build product of these bytes (the result cache, by contrast, keys on the physics'
    version, not on bytes)."""
    h = hashlib.sha256()
    for path in sorted(folder.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def _kernel_cache_dir() -> Path:
    # the base is kept in its own variable: NUMBA_CACHE_DIR is set to the hashed folder below,
    # and processes started from this one (workers) must not nest a second hash in it
    base = (
        os.environ.get(_BASE)
        or os.environ.get("NUMBA_CACHE_DIR")
        or os.path.join(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache", "insect-gait")
    )
    os.environ[_BASE] = base
    return Path(base) / f"numba-{source_hash(Path(__file__).resolve().parent)}"


def _use_kernel_cache() -> None:
    """Point numba's cache at `_kernel_cache_dir` (numba reads it when a kernel is decorated,
    so this works whether or not numba was imported before)."""
    path = str(_kernel_cache_dir())
    numba = sys.modules.get("numba")
    if numba is not None:
        numba.config.CACHE_DIR = path
    os.environ["NUMBA_CACHE_DIR"] = path  # numba imported later, and worker processes


_use_kernel_cache()

"""Names of the runs' machinery that load nothing (no MuJoCo, no numba): the backends
`reproduce --backend` offers (implemented in sim_core.runs.backends) and where the result cache
lives, so that building the CLI's parser or the service's settings costs no engine import.

The result cache is one folder per installation, shared by every door that simulates: the
command line (`reproduce`, `surface`, `atlas`, the lab), the REST service's jobs and, through
them, the viewer's job buttons. `default_cache_dir` is that folder: $INSECT_GAIT_CACHE_DIR if
set; else the checkout's out/cache when the package runs from a checkout (the folder `make run`,
`make test` and every command run from the checkout's root have always used); else the user's
cache folder ($XDG_CACHE_HOME or ~/.cache, /insect-gait), for an install outside a checkout.
Its size limit (least recently used results evicted first, `sim_core.runs.cache`) is
$INSECT_GAIT_CACHE_MAX_BYTES, else `DEFAULT_CACHE_MAX_BYTES`.
"""

from __future__ import annotations

import os
from pathlib import Path

BACKENDS = ("local", "dask", "ray", "inline")

CACHE_DIR_ENV = "INSECT_GAIT_CACHE_DIR"
CACHE_MAX_BYTES_ENV = "INSECT_GAIT_CACHE_MAX_BYTES"
# 2 GiB: about 250,000 finished simulations at the ~8 KB one takes (a whole `reproduce` of the
# paper holds ~7,000 in 55 MB), small beside a disk, large enough that no study evicts its own
# runs while it resumes
DEFAULT_CACHE_MAX_BYTES = 2 * 1024**3
# the checkout this package sits in (sim_core/runs/__init__.py -> the repository root)
_CHECKOUT = Path(__file__).resolve().parents[2]


def default_cache_dir() -> Path:
    """The installation's result cache: $INSECT_GAIT_CACHE_DIR, the checkout's out/cache, or
    the user's cache folder's insect-gait (module doc)."""
    env = os.environ.get(CACHE_DIR_ENV, "").strip()
    if env:
        return Path(env).expanduser()
    if (_CHECKOUT / "pyproject.toml").is_file() and (_CHECKOUT / "sim_core").is_dir():
        return _CHECKOUT / "out" / "cache"
    base = os.environ.get("XDG_CACHE_HOME", "").strip() or str(Path.home() / ".cache")
    return Path(base) / "insect-gait"


def default_cache_max_bytes() -> int | None:
    """The cache's size limit in bytes: $INSECT_GAIT_CACHE_MAX_BYTES read by
    `cache_max_bytes_of`, else `DEFAULT_CACHE_MAX_BYTES`."""
    raw = os.environ.get(CACHE_MAX_BYTES_ENV, "").strip()
    return cache_max_bytes_of(raw) if raw else DEFAULT_CACHE_MAX_BYTES


def cache_max_bytes_of(raw: str | int | None) -> int | None:
    """A size limit as given (the variable's text, a flag, a setting): a whole number of bytes,
    or 0 / "none" / None for no limit. Raises ValueError saying what it takes."""
    if raw is None or (isinstance(raw, str) and raw.strip().lower() in ("none", "")):
        return None
    try:
        value = int(raw)
    except ValueError:
        value = -1
    if value < 0:
        raise ValueError(
            f"the cache's size limit ({CACHE_MAX_BYTES_ENV}) is {raw!r}: give a size in bytes "
            "(a whole number), or 0 or 'none' for no limit"
        )
    return value or None

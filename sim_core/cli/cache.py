"""`cache info | trim | clear`: the result cache every door shares (`reproduce`, `surface`,
`atlas`, the lab and the REST service's jobs), looked at and tidied without loading the engine.

The folder and its size limit are the installation's (`sim_core.runs.default_cache_dir`,
$INSECT_GAIT_CACHE_DIR; $INSECT_GAIT_CACHE_MAX_BYTES): the same the API's workers use unless
it was started with another."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

from sim_core.cli.common import UsageError
from sim_core.runs import (
    CACHE_DIR_ENV,
    CACHE_MAX_BYTES_ENV,
    cache_max_bytes_of,
    default_cache_dir,
    default_cache_max_bytes,
)
from sim_core.runs.cache import CacheUsage, ResultCache


def register(sub: Any) -> None:
    p = sub.add_parser(
        "cache",
        help="the result cache shared by the CLI and the API: info, trim, clear",
        description="The folder of finished simulations that every command and the REST "
        f"service read back instead of recomputing (${CACHE_DIR_ENV}; its size limit "
        f"${CACHE_MAX_BYTES_ENV}, least recently used results evicted first).",
    )
    p.add_argument("action", choices=("info", "trim", "clear"),
                   help="info: where it is, how many results, their bytes and the limit; "
                   "trim: evict the least recently used results down to the limit now; "
                   "clear: delete every result")  # fmt: skip
    p.add_argument("--cache", type=Path, default=None,
                   help=f"the cache folder (default: ${CACHE_DIR_ENV}, else "
                   f"{default_cache_dir()})")  # fmt: skip
    p.add_argument("--max-bytes", default=None,
                   help=f"the size limit for info and trim, bytes (0 or 'none': no limit; "
                   f"default: ${CACHE_MAX_BYTES_ENV}, else 2 GiB)")  # fmt: skip
    p.add_argument("--json", action="store_true", help="print the answer as one JSON object")
    p.set_defaults(func=_cmd_cache)


def _cmd_cache(args: argparse.Namespace) -> int:
    try:
        limit = (default_cache_max_bytes() if args.max_bytes is None
                 else cache_max_bytes_of(args.max_bytes))  # fmt: skip
    except ValueError as exc:
        raise UsageError(f"--max-bytes: {exc}") from None
    cache = ResultCache(args.cache or default_cache_dir(), max_bytes=limit)
    if args.action == "info":
        usage = cache.usage()
        print(json.dumps(usage_json(usage)) if args.json else usage_words(usage))
        return 0
    gone = cache.trim() if args.action == "trim" else cache.clear()
    left = cache.usage()
    if args.json:
        print(
            json.dumps(
                {
                    "removed": gone.entries,
                    "removed_bytes": gone.bytes,
                    "stale_temporary_removed": gone.temporary,
                    **usage_json(left),
                }
            )
        )
    else:  # fmt: skip
        print(f"removed {gone.entries} result(s), {_size(gone.bytes)}; {usage_words(left)}")
    if args.action == "trim" and limit is None:
        print("(no size limit is set, so nothing is evicted)", file=sys.stderr)
    return 0


def usage_json(u: CacheUsage) -> dict[str, Any]:
    return {"location": str(u.root.resolve()), "entries": u.entries, "bytes": u.bytes,
            "max_bytes": u.max_bytes, "oldest_use": u.oldest_use, "newest_use": u.newest_use,
            "temporary_files": u.temporary}  # fmt: skip


def usage_words(u: CacheUsage) -> str:
    """The cache in a few lines: where, how much, the limit, how old."""
    limit = (
        "no limit"
        if u.max_bytes is None
        else (f"limit {_size(u.max_bytes)} ({100 * u.bytes / max(1, u.max_bytes):.0f}% used)")
    )
    lines = [f"cache: {u.root.resolve()}",
             f"  {u.entries} result(s), {_size(u.bytes)}; {limit}"]  # fmt: skip
    if u.oldest_use is not None and u.newest_use is not None:
        lines.append(f"  last used from {_when(u.oldest_use)} to {_when(u.newest_use)}")
    if u.temporary:
        lines.append(f"  {u.temporary} temporary file(s): writes in progress, or left by a "
                     "killed writer (trim removes those older than an hour)")  # fmt: skip
    return "\n".join(lines)


def _size(n: int) -> str:
    for unit, k in (("GiB", 1024**3), ("MiB", 1024**2), ("KiB", 1024)):
        if n >= k:
            return f"{n / k:.1f} {unit} ({n} bytes)"
    return f"{n} bytes"


def _when(t: float) -> str:
    return time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(t))

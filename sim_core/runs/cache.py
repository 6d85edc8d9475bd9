"""Task results on disk, one JSON file per task named by the task's content hash.

Why files and not a database: a result is written once and never changed, any number of
processes may write different results at the same time, and an interrupted run must leave
nothing half-written. Each file is written to a temporary name in the same folder
(`.<key>.<random>.tmp`) and renamed into place (`os.replace` is atomic on POSIX and Windows),
so a reader sees either no file or a whole one. A file whose stored task differs from the one
asked for (a hash collision, or a hand-edited file) or that does not parse is treated as missing
and recomputed.

The cache is shared (one per installation, `sim_core.runs.default_cache_dir`: the command line,
the REST service's workers, a Dask client) and bounded: a read touches the file's modification
time (`os.utime`), so the oldest time is the least recently used result, and `trim` deletes
results from the oldest until the folder holds at most `LOW_WATER` of `max_bytes`, so that one
trim makes room for many results rather than one. Trimming is safe beside other processes:
it deletes only whole `<key>.json` files (never a temporary file still being written: a
temporary file is removed only once it is `STALE_TMP_S` old, i.e. left by a killed writer), and
a result deleted under a reader's feet is only recomputed, never wrong.
"""

from __future__ import annotations

import json
import os
import re
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the cache itself loads no engine: `insect-gait cache info` stays light
    from sim_core.runs.tasks import Task

# a trim leaves the folder at this share of its limit
LOW_WATER = 0.9
# a temporary file this old was left by a writer that died: no write of one result takes an hour
STALE_TMP_S = 3600.0
_RESULT = re.compile(r"[0-9a-f]{24}\.json")
_TMP = re.compile(r"\.[0-9a-f]{24}\..*\.tmp")


@dataclass(frozen=True)
class CacheUsage:
    """What a cache folder holds: `entries` results of `bytes` in all, under `root`, with its
    limit (`max_bytes`, None: none); the oldest and newest use (a read or a write) as Unix
    times, None when empty; `temporary`: files of writes in progress or left by killed ones."""

    root: Path
    entries: int
    bytes: int
    max_bytes: int | None
    oldest_use: float | None
    newest_use: float | None
    temporary: int


@dataclass(frozen=True)
class Trimmed:
    """What a `trim` or `clear` removed: results and their bytes, and stale temporary files."""

    entries: int
    bytes: int
    temporary: int


class ResultCache:
    """`get`/`put` of task results under `root` (created on first write), at most `max_bytes`
    (None: unbounded) once `trim` has run."""

    def __init__(self, root: Path | str, max_bytes: int | None = None) -> None:
        self.root = Path(root)
        self.max_bytes = max_bytes
        # what the last scan found plus what this object wrote since, and when: `maybe_trim`
        # scans the folder again only when that could be over the limit, or once a minute
        # (other processes write too)
        self._bytes_seen: int | None = None
        self._scanned_at = 0.0

    def path(self, task: Task) -> Path:
        return self.root / f"{task.key}.json"

    def get(self, task: Task) -> dict[str, Any] | None:
        p = self.path(task)
        try:
            stored = json.loads(p.read_text())
        except (OSError, ValueError):
            return None
        if not isinstance(stored, dict) or stored.get("task") != _task_json(task):
            return None
        result = stored.get("result")
        if not isinstance(result, dict):
            return None
        try:  # used now: the last to be evicted (a read-only cache is simply not reordered)
            os.utime(p)
        except OSError:
            pass
        return result

    def put(self, task: Task, result: dict[str, Any]) -> None:
        self.root.mkdir(parents=True, exist_ok=True)
        text = json.dumps({"task": _task_json(task), "result": result}, allow_nan=False)
        fd, tmp = tempfile.mkstemp(dir=self.root, prefix=f".{task.key}.", suffix=".tmp")
        try:
            with os.fdopen(fd, "w") as f:
                f.write(text)
            os.replace(tmp, self.path(task))
            if self._bytes_seen is not None:
                self._bytes_seen += len(text)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise

    def __contains__(self, task: Task) -> bool:
        return self.get(task) is not None

    # ---- the folder as a whole -----------------------------------------------------------

    def _scan(self) -> tuple[list[tuple[float, int, Path]], list[tuple[float, Path]]]:
        """(last use, size, path) of every result and (mtime, path) of every temporary file."""
        results: list[tuple[float, int, Path]] = []
        temporary: list[tuple[float, Path]] = []
        try:
            entries = list(os.scandir(self.root))
        except FileNotFoundError:
            return results, temporary
        for e in entries:
            try:
                if _RESULT.fullmatch(e.name):
                    st = e.stat(follow_symlinks=False)
                    results.append((st.st_mtime, st.st_size, Path(e.path)))
                elif _TMP.fullmatch(e.name):
                    temporary.append((e.stat(follow_symlinks=False).st_mtime, Path(e.path)))
            except FileNotFoundError:  # deleted meanwhile by another process
                continue
        return results, temporary

    def usage(self) -> CacheUsage:
        """How many results the folder holds, their bytes, and the limit."""
        results, temporary = self._scan()
        uses = [t for t, _, _ in results]
        return CacheUsage(
            root=self.root, entries=len(results), bytes=sum(s for _, s, _ in results),
            max_bytes=self.max_bytes, oldest_use=min(uses, default=None),
            newest_use=max(uses, default=None), temporary=len(temporary),
        )  # fmt: skip

    def trim(self, max_bytes: int | None = None) -> Trimmed:
        """Keep the folder within `max_bytes` (default: this cache's limit; None: no limit):
        once over it, the least recently used results go until `LOW_WATER` of it is left.
        Temporary files left by killed writers (older than `STALE_TMP_S`) go too."""
        limit = self.max_bytes if max_bytes is None else max_bytes
        results, temporary = self._scan()
        gone_tmp = _remove_stale(temporary)
        total = sum(s for _, s, _ in results)
        n = freed = 0
        if limit is not None and total > limit:
            target = int(limit * LOW_WATER)
            for _, size, path in sorted(results, key=lambda r: r[0]):
                if total - freed <= target:
                    break
                try:
                    path.unlink()
                except FileNotFoundError:  # another process trimmed it first
                    pass
                n, freed = n + 1, freed + size
        self._bytes_seen, self._scanned_at = total - freed, time.monotonic()
        return Trimmed(n, freed, gone_tmp)

    def maybe_trim(self, every_s: float = 60.0) -> Trimmed | None:
        """`trim` to this cache's limit, unless the last scan (plus what this object wrote
        since) is under it and younger than `every_s`: a loop of many small runs (the
        finder's rounds) scans the folder about once a minute, not once a round."""
        if self.max_bytes is None:
            return None
        fresh = time.monotonic() - self._scanned_at < every_s
        if fresh and self._bytes_seen is not None and self._bytes_seen <= self.max_bytes:
            return None
        return self.trim()

    def clear(self) -> Trimmed:
        """Delete every result (and stale temporary files); writes in progress finish."""
        results, temporary = self._scan()
        for _, _, path in results:
            path.unlink(missing_ok=True)
        return Trimmed(len(results), sum(s for _, s, _ in results), _remove_stale(temporary))


def _remove_stale(temporary: list[tuple[float, Path]]) -> int:
    cutoff = time.time() - STALE_TMP_S
    stale = [p for t, p in temporary if t < cutoff]
    for p in stale:
        p.unlink(missing_ok=True)
    return len(stale)


def _task_json(task: Task) -> Any:
    """The task as stored (JSON round trip, so tuples and lists compare equal)."""
    return json.loads(json.dumps(asdict(task)))

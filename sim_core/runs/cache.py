"""Task results on disk, one JSON file per task named by the task's content hash.

Why files and not a database: a result is written once and never changed, any number of
processes may write different results at the same time, and an interrupted run must leave
nothing half-written. Each file is written to a temporary name in the same folder and renamed
into place (`os.replace` is atomic on POSIX and Windows), so a reader sees either no file or a
whole one. A file whose stored task differs from the one asked for (a hash collision, or a
hand-edited file) or that does not parse is treated as missing and recomputed.
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import asdict
from pathlib import Path
from typing import Any

from sim_core.runs.tasks import Task


class ResultCache:
    """`get`/`put` of task results under `root` (created on first write)."""

    def __init__(self, root: Path | str) -> None:
        self.root = Path(root)

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
        return result if isinstance(result, dict) else None

    def put(self, task: Task, result: dict[str, Any]) -> None:
        self.root.mkdir(parents=True, exist_ok=True)
        text = json.dumps({"task": _task_json(task), "result": result}, allow_nan=False)
        fd, tmp = tempfile.mkstemp(dir=self.root, prefix=f".{task.key}.", suffix=".tmp")
        try:
            with os.fdopen(fd, "w") as f:
                f.write(text)
            os.replace(tmp, self.path(task))
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise

    def __contains__(self, task: Task) -> bool:
        return self.get(task) is not None


def _task_json(task: Task) -> Any:
    """The task as stored (JSON round trip, so tuples and lists compare equal)."""
    return json.loads(json.dumps(asdict(task)))

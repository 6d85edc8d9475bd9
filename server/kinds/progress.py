"""A job's progress that moves inside a chunk of runs, not only when the core reports.

Why: the drift surface and the atlas (`sim_core.drift_surface`, `surface_atlas`) report their
share done (`on_progress`) when a chunk of runs finishes (up to `SurfaceConfig.chunk_size`, 8
probes), so a job of one chunk sat at progress 0.00 until it was done, and its ETA had only the
history to go on. The core's `executor` hook runs each chunk: run here by the core's own
`execute_chunk` with its progress callback (the share of the chunk's simulated time done,
about every 1 %), the job's progress moves between the core's reports. Nothing simulated
changes: the chunk is run by the same function the core would call.

Between two reports the job moves by the chunk's runs times the share per run the core's last
report showed (the rise over that chunk's runs); before the first report, by the job's size
(`run_count`, the surface's first pass). The core's reports stay authoritative; what is shown
never goes back and stops at `CAP` until the result is stored (then the store sets 1).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import sim_core
from server.kinds.base import Progress

CAP = 0.99  # a runner never says 1: the job is done when its result is stored


@dataclass
class ChunkProgress:
    """`on_progress` and `executor` for the core's surface functions, reporting to `report`.

    Args:
        report: the job's progress callback (the worker's, throttled there).
        runs: the runs the job is sized at; 1 / runs is the share per run until the core's
            first report measures it.
        nthread: threads each chunk's physics steps on (`execute_chunk`; the numbers do not
            depend on it).
    """

    report: Progress
    runs: int
    nthread: int = 1
    done: float = 0.0  # the core's last report, 0..1
    per_run: float = field(init=False)
    shown: float = 0.0
    _chunk: int = 0

    def __post_init__(self) -> None:
        self.per_run = 1.0 / max(1, self.runs)

    def show(self, x: float) -> None:
        """Report `x` (capped at CAP) if it is ahead of what was shown."""
        x = min(CAP, x)
        if x > self.shown:
            self.shown = x
            self.report(x)

    def on_progress(self, x: float) -> None:
        """The core's share done after a chunk; the share per run of the next chunks."""
        if self._chunk and x > self.done:
            self.per_run = (x - self.done) / self._chunk
        self.done = x
        self.show(x)

    def executor(self, chunk: Sequence[sim_core.Task]) -> list[dict[str, Any]]:
        """Run `chunk` as the core would (`execute_chunk`), moving the progress as it runs."""
        self._chunk = len(chunk)
        base, span = self.done, len(chunk) * self.per_run
        return sim_core.execute_chunk(
            chunk, lambda f: self.show(base + f * span), nthread=self.nthread
        )

"""Time estimates from the job table: how long a running job still needs, and when a slot in a
full queue frees (`Retry-After`). Pure functions of what the store reports, so they are tested
without clocks."""

from __future__ import annotations

import math
from collections.abc import Sequence
from datetime import datetime
from typing import Any

from server.jobs import JobRow
from server.kinds.base import step_weight
from server.status import JobStatus

MIN_PROGRESS = 0.02  # below this, progress says too little to extrapolate from
# no history yet: wall s per simulated s at the default step (measured 0.49 for one
# implicitfast run on the 2-core development machine: 24.5 us per step)
FALLBACK_WALL_PER_SIM_S = 0.5
RETRY_NO_WORKERS_S = 60  # nothing drains the queue; ask again in a minute
RETRY_MAX_S = 3600


def seconds_since(stamp: str | None, now: datetime) -> float | None:
    if stamp is None:
        return None
    started = datetime.fromisoformat(stamp.replace("Z", "+00:00"))
    return max(0.0, (now - started).total_seconds())


def remaining_s(
    *,
    elapsed_s: float,
    progress: float,
    sim_seconds: float,
    wall_per_sim_s: float | None,
    moving_s: float | None = None,
) -> float:
    """Seconds a running job still needs.

    Args:
        elapsed_s: wall seconds since it started.
        progress: its reported progress, 0..1.
        sim_seconds: simulated seconds it asks for (all runs), weighted by its step
            (`step_weight`: a second at 5e-6 s counts 10).
        wall_per_sim_s: recent jobs' wall seconds per (weighted) simulated second, or None.
        moving_s: wall seconds since it first reported progress above 0 (None: not yet, or
            a row from an older server: then `elapsed_s`).

    Returns:
        From its own rate once it has reported `MIN_PROGRESS` (moving x (1 - p) / p: the
        rate since its progress began to move, so that the seconds before its first run
        reports (loading the engine, building the model), which do not scale with the job, are
        not extrapolated over the rest: a 7.6 s surface job, the first on its worker, spent
        2.5 s so and was told 52 s left at 5.6 %); before that,
        from recent jobs' rate x its size, less the time already spent.
    """
    if progress >= 1.0:
        return 0.0
    rated = elapsed_s if moving_s is None else moving_s
    if progress >= MIN_PROGRESS and rated > 0:
        return rated * (1.0 - progress) / progress
    rate = wall_per_sim_s if wall_per_sim_s is not None else FALLBACK_WALL_PER_SIM_S
    return max(0.0, sim_seconds * rate - elapsed_s)


def retry_after_s(*, workers: int, running_remaining_s: list[float]) -> int:
    """Seconds until a slot in a full queue frees: the soonest a busy worker finishes (it then
    takes the oldest queued job). At least 1, at most an hour; 60 with no workers."""
    if workers == 0:
        return RETRY_NO_WORKERS_S
    if not running_remaining_s or len(running_remaining_s) < workers:
        return 1  # an idle worker is about to take a queued job
    soonest = min(running_remaining_s)
    return int(min(RETRY_MAX_S, max(1, math.ceil(soonest))))


def weighted_sim_seconds(sim_seconds: float, spec: dict[str, Any] | None) -> float:
    """Simulated seconds at the default step that take as many physics steps as the job's."""
    if not spec:
        return sim_seconds
    try:
        return sim_seconds * step_weight(spec)
    except (ValueError, TypeError, ZeroDivisionError):  # a row written by an older server
        return sim_seconds


def wall_per_sim_second(done: Sequence[tuple[float, float, dict[str, Any]]]) -> float | None:
    """Wall seconds per (weighted) simulated second of done jobs, given as (wall seconds,
    simulated seconds, spec) (`JobStore.recent_done`), pooled: their wall time over their
    simulated time, so each simulated second weighs once. A small job's fixed cost (a worker
    loading the engine, a model built: seconds against a fraction of a simulated second) then
    cannot set the rate of a long one, as the median of per-job rates let it (a 0.3 s job that
    took 5 s said 17 wall s per simulated s). None without any."""
    pairs = [(wall, w) for wall, sim, spec in done if (w := weighted_sim_seconds(sim, spec)) > 0]
    total = sum(w for _, w in pairs)
    return sum(wall for wall, _ in pairs) / total if pairs else None


def eta_of(job: JobRow, now: datetime, wall_per_sim_s: float | None) -> float | None:
    """`remaining_s` for a running job as the store returns it; None for any other state. Its
    size is its simulated seconds weighted by its step (`weighted_sim_seconds`), so a job at
    dt_s 1e-6 s is estimated 50 times longer than the same job at the default 5e-5 s."""
    if job.status is not JobStatus.RUNNING:
        return None
    elapsed = seconds_since(job.started_at, now)
    if elapsed is None:
        return None
    sim = weighted_sim_seconds(job.sim_seconds, job.spec)
    return round(
        remaining_s(
            elapsed_s=elapsed,
            progress=job.progress,
            sim_seconds=sim,
            wall_per_sim_s=wall_per_sim_s,
            moving_s=seconds_since(job.moving_since, now),
        ),
        1,
    )

"""What each job kind does, in one place, so that new kinds (the experiments) plug in here.

Runs only inside worker processes. Every runner returns a JSON-able dict with a `records` list of
flat rows (the CSV export and the figure read those) plus whatever else the kind keeps. A runner
never returns numbers from a diverged simulation: it raises `JobFailed` naming the run.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from server.schemas import AnyJob, BifurcationJob, ReturnMapJob, RunJob, SweepJob

Progress = Callable[[float], None]


class JobFailed(Exception):
    """A refusal or failure whose message is meant for the client, as is."""


def _core() -> Any:
    """Import the core lazily: the API process never needs it to validate or queue a job."""
    try:
        import sim_core
    except Exception as exc:  # an unfinished or broken core must fail jobs, not the worker
        raise JobFailed(f"sim_core could not be imported: {type(exc).__name__}: {exc}") from exc
    return sim_core


def _batch(core: Any, job: RunJob | ReturnMapJob, progress: Progress, nthread: int) -> list[Any]:
    specs = [core.RunSpec(beta=job.beta, d31_init=d, **job.run_fields()) for d in job.d31_init]
    try:
        results: list[Any] = core.simulate_batch(specs, nthread=nthread, progress=progress)
    except core.SimulationDiverged as exc:
        raise JobFailed(f"{exc}; try a smaller dt_s or another integrator") from exc
    diverged = [
        f"run {i + 1} of {len(results)} (d31_init = {d:.4g}): {r.error}"
        for i, (d, r) in enumerate(zip(job.d31_init, results, strict=True))
        if r.diverged
    ]
    if diverged:
        raise JobFailed(
            f"{len(diverged)} of {len(results)} simulation(s) diverged, so the job returns no "
            "numbers; try a smaller dt_s or another integrator. " + "; ".join(diverged)
        )
    return results


def _summary_row(d31_init: float, summary: dict[str, Any]) -> dict[str, Any]:
    row = {"d31_init": d31_init}
    row.update({k: v for k, v in summary.items() if k not in ("d31", "error", "diverged")})
    row["n_touchdowns"] = len(summary.get("d31") or [])
    return row


def run_job(job: RunJob, progress: Progress, nthread: int) -> dict[str, Any]:
    core = _core()
    results = _batch(core, job, progress, nthread)
    runs = [r.to_dict() if job.include_series else r.summary() for r in results]
    records = [_summary_row(d, r.summary()) for d, r in zip(job.d31_init, results, strict=True)]
    return {"kind": "run", "runs": runs, "records": records}


def return_map_job(job: ReturnMapJob, progress: Progress, nthread: int) -> dict[str, Any]:
    """The paper's Fig. 7 construction: Delta31 at touchdown n against touchdown n + lag."""
    core = _core()
    results = _batch(core, job, progress, nthread)
    records: list[dict[str, Any]] = []
    for d0, res in zip(job.d31_init, results, strict=True):
        d31 = [float(x) for x in res.summary()["d31"]]
        for n in range(len(d31) - job.lag):
            records.append(
                {"d31_init": d0, "n": n, "d31_n": d31[n], "d31_n_plus_lag": d31[n + job.lag]}
            )
    runs = [r.summary() for r in results]
    return {
        "kind": "return_map",
        "beta": job.beta,
        "lag": job.lag,
        "records": records,
        "runs": runs,
    }


def _grid(
    core: Any, job: SweepJob | BifurcationJob, progress: Progress, nthread: int
) -> list[tuple[float, float, Any]]:
    """Every (beta, d31_init) of the job's grid as independent runs, one batch call."""
    pairs = [(b, d) for b in job.beta_range.values() for d in job.d31_init]
    specs = [core.RunSpec(beta=b, d31_init=d, **job.run_fields()) for b, d in pairs]
    results = core.simulate_batch(specs, nthread=nthread, progress=progress)
    diverged = [
        f"beta {b:.4g}, d31_init {d:.4g}: {r.error}"
        for (b, d), r in zip(pairs, results, strict=True)
        if r.diverged
    ]
    if diverged:
        raise JobFailed(
            f"{len(diverged)} of {len(results)} simulation(s) diverged, so the job returns no "
            "numbers; try a smaller dt_s or another integrator. " + "; ".join(diverged)
        )
    return [(b, d, r) for (b, d), r in zip(pairs, results, strict=True)]


def sweep_job(job: SweepJob, progress: Progress, nthread: int) -> dict[str, Any]:
    """Final Delta31 and gait for every beta of the grid and every initial Delta31."""
    core = _core()
    records = []
    for beta, d0, res in _grid(core, job, progress, nthread):
        row = _summary_row(d0, res.summary())
        row["beta"] = beta
        records.append(row)
    return {"kind": "sweep", "records": records}


def bifurcation_job(job: BifurcationJob, progress: Progress, nthread: int) -> dict[str, Any]:
    """Where Delta31 settles after the transient, per beta and initial value (Fig. 8's stable
    branches); runs still drifting at the end are kept but flagged `settled: false`."""
    core = _core()
    records = []
    for beta, d0, res in _grid(core, job, progress, nthread):
        after = [float(x) for t, x in zip(res.d31_times_s, res.d31, strict=True)
                 if t >= job.transient_s]  # fmt: skip
        mean = core.circular_mean(after) if after else None
        settled = res.d31_final is not None and res.gait != "other"
        records.append(
            {"beta": beta, "d31_init": d0, "d31_after_transient": mean,
             "n_touchdowns": len(after), "gait": core.classify_gait(mean) if mean is not None
             else "other", "settled": settled}
        )  # fmt: skip
    return {"kind": "bifurcation", "records": records}


RUNNERS: dict[str, Callable[[Any, Progress, int], dict[str, Any]]] = {
    "run": run_job,
    "return_map": return_map_job,
    "sweep": sweep_job,
    "bifurcation": bifurcation_job,
}


def execute(job: AnyJob, progress: Progress, nthread: int) -> dict[str, Any]:
    result = RUNNERS[job.kind](job, progress, nthread)
    _check_finite(result)
    return result


def _check_finite(obj: Any, path: str = "result") -> None:
    """JSON has no NaN; a non-finite number means a broken run, which must not pass as data."""
    if isinstance(obj, float) and not math.isfinite(obj):
        raise JobFailed(f"the simulation produced a non-finite number at {path}")
    if isinstance(obj, dict):
        for k, v in obj.items():
            _check_finite(v, f"{path}.{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            _check_finite(v, f"{path}[{i}]")

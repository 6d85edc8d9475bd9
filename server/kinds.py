"""What each job kind does, in one place, so that new kinds (the experiments) plug in here.

Runs only inside worker processes. Every runner returns a JSON-able dict with a `records` list of
flat rows (the CSV export and the figure read those) plus whatever else the kind keeps. A runner
never returns numbers from a diverged simulation: it raises `JobFailed` naming the run.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from server.schemas import (
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    MAX_STABLE_DT_S,
    AnyJob,
    BifurcationJob,
    HysteresisJob,
    ReturnMapJob,
    RunJob,
    SweepJob,
    _Physics,
    tidy,
)

# Columns of each kind's `records`, so that an empty table still has its header.
RECORD_COLUMNS: dict[str, list[str]] = {
    "run": ["d31_init", "beta", "d31_final", "gait", "speed_cm_s", "duty_factor_measured",
            "slip_fraction", "landing_swing_share", "retouches_per_stance", "n_touchdowns"],
    "return_map": ["d31_init", "n", "d31_n", "d31_n_plus_lag"],
    "sweep": ["d31_init", "beta", "d31_final", "gait", "speed_cm_s", "duty_factor_measured",
              "slip_fraction", "landing_swing_share", "retouches_per_stance", "n_touchdowns"],
    "bifurcation": ["beta", "d31_init", "d31_after_transient", "n_touchdowns", "gait",
                    "settled"],
    "hysteresis": ["time_s", "leg", "value", "d31"],
}  # fmt: skip
# The time-series tables of a run job with include_series (`?table=` of the CSV export).
SERIES_COLUMNS: dict[str, list[str]] = {
    "d31": ["run", "d31_init", "n", "time_s", "d31"],
    "samples": ["run", "d31_init", "time_s", "stance_R1", "stance_L1", "stance_R2",
                "stance_L2", "stance_R3", "stance_L3", "x_m", "y_m", "z_m"],
}  # fmt: skip

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


def advice(job: _Physics, errors: list[str]) -> str:
    """What the client can do about failed runs: a smaller step only where the step is the
    likely cause (a numerical blow-up, or a step coarser than the converged default); a fall
    or flip at a sound step is the insect's physics under these conditions."""
    integrator = job.integrator or DEFAULT_INTEGRATOR
    dt = job.dt_s or DEFAULT_DT_S
    text = " ".join(errors)
    numerical = any(w in text for w in ("MuJoCo warning", "non-finite", "unstable"))
    if numerical or dt > DEFAULT_DT_S * (1 + 1e-9):
        return (
            f"the timestep is the likely cause ({integrator} at dt_s {dt:g} s): try a smaller "
            f"dt_s (the converged default is {DEFAULT_INTEGRATOR} at {DEFAULT_DT_S:g} s; "
            f"{integrator} is stable up to {MAX_STABLE_DT_S[integrator]:g} s)"
        )
    return (
        f"the insect fell over under these conditions (slope_deg {job.slope_deg:g}, "
        f"body_mass_g {job.body_mass_g:g}); this is the model's physics at a converged "
        "timestep, not a numerical problem, so a smaller dt_s will not help: change the "
        "conditions"
    )


def _failed(job: _Physics, diverged: list[str], total: int) -> JobFailed:
    return JobFailed(
        f"{len(diverged)} of {total} simulation(s) failed, so the job returns no numbers; "
        f"{advice(job, diverged)}. " + "; ".join(diverged)
    )


def _batch(core: Any, job: RunJob | ReturnMapJob, progress: Progress, nthread: int) -> list[Any]:
    specs = [core.RunSpec(beta=job.beta, d31_init=d, **job.run_fields()) for d in job.d31_init]
    try:
        results: list[Any] = core.simulate_batch(specs, nthread=nthread, progress=progress)
    except core.SimulationDiverged as exc:
        raise JobFailed(f"{exc}; {advice(job, [str(exc)])}") from exc
    diverged = [
        f"run {i + 1} of {len(results)} (d31_init = {d:.4g}): {r.error}"
        for i, (d, r) in enumerate(zip(job.d31_init, results, strict=True))
        if r.diverged
    ]
    if diverged:
        raise _failed(job, diverged, len(results))
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
    out: dict[str, Any] = {"kind": "run", "runs": runs, "records": records}
    if job.include_series:
        out["series"] = series_tables(job.d31_init, runs)
    return out


def series_tables(d31_init: list[float], runs: list[dict[str, Any]]) -> dict[str, Any]:
    """The time series as flat tables: Delta31 at each leg-1 touchdown, and every recorded
    sample (stance per leg in the paper's order 1..6 = R1 L1 R2 L2 R3 L3, as
    `sim_core.leg_names()`; body position, m)."""
    legs = SERIES_COLUMNS["samples"][3:9]
    d31_rows: list[dict[str, Any]] = []
    samples: list[dict[str, Any]] = []
    for k, (d0, run) in enumerate(zip(d31_init, runs, strict=True)):
        for n, (t, d) in enumerate(zip(run["d31_times_s"], run["d31"], strict=True)):
            d31_rows.append({"run": k, "d31_init": d0, "n": n, "time_s": t, "d31": d})
        for t, stance, pos in zip(run["times_s"], run["stance"], run["body_pos_m"], strict=True):
            row: dict[str, Any] = {"run": k, "d31_init": d0, "time_s": t}
            row.update({leg: int(on) for leg, on in zip(legs, stance, strict=True)})
            row.update({"x_m": pos[0], "y_m": pos[1], "z_m": pos[2]})
            samples.append(row)
    return {"d31": d31_rows, "samples": samples}


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
    specs = core.spec_grid(job.beta_range.values(), job.d31_init, **job.run_fields())
    results = core.simulate_batch(specs, nthread=nthread, progress=progress)
    diverged = [
        f"beta {b:.4g}, d31_init {d:.4g}: {r.error}"
        for (b, d), r in zip(pairs, results, strict=True)
        if r.diverged
    ]
    if diverged:
        raise _failed(job, diverged, len(results))
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


def hysteresis_job(job: HysteresisJob, progress: Progress, nthread: int) -> dict[str, Any]:
    """Fig. 6a / 9: one run ramping `parameter` start -> turn -> start; Delta31 against the
    value at every leg-1 touchdown, and the transitions on each leg of the ramp."""
    core = _core()
    spec = core.RunSpec(**job.run_fields())
    res = core.sweep(
        spec,
        parameter=job.parameter,
        turn=job.turn,
        hold_s=job.hold_s,
        ramp_s=job.ramp_s,
        progress=progress,
    )
    if res.error:
        raise _failed(job, [f"the sweep run: {res.error}"], 1)
    turn_t = job.hold_s + job.ramp_s
    records = [
        {"time_s": t, "leg": "first" if t < turn_t else "second", "value": v, "d31": d}
        for t, v, d in zip(res.times_s, res.values, res.d31, strict=True)
    ]
    progress(1.0)
    return {
        "kind": "hysteresis",
        "parameter": res.parameter,
        "start": job.start,
        "turn": job.turn,
        "summary": res.summary,
        "records": records,
    }


RUNNERS: dict[str, Callable[[Any, Progress, int], dict[str, Any]]] = {
    "run": run_job,
    "return_map": return_map_job,
    "sweep": sweep_job,
    "bifurcation": bifurcation_job,
    "hysteresis": hysteresis_job,
}


def execute(job: AnyJob, progress: Progress, nthread: int) -> dict[str, Any]:
    result = RUNNERS[job.kind](job, progress, nthread)
    _check_finite(result)
    out: dict[str, Any] = _tidy(result)
    return out


def _tidy(obj: Any) -> Any:
    """Floats to 12 significant digits (0.66, not 0.6599999999999999): far below any physical
    resolution of the model, and what a person reads back is what they sent."""
    if isinstance(obj, float):
        return tidy(obj)
    if isinstance(obj, dict):
        return {k: _tidy(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_tidy(v) for v in obj]
    return obj


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

"""What each job kind does, in one place, so that new kinds (the experiments) plug in here.

Runs only inside worker processes. Every runner returns a JSON-able dict with a `records` list of
flat rows (the CSV export and the figure read those) plus whatever else the kind keeps. A runner
never returns numbers from a diverged simulation: it raises `JobFailed` naming the run.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict
from typing import Any

from server.schemas import (
    AnyJob,
    AtlasJob,
    BifurcationJob,
    HysteresisJob,
    ReturnMapJob,
    RunJob,
    SweepJob,
    _Physics,
    tidy,
)
from sim_core.contract import (
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    LEG_NAMES,
    MAX_STABLE_DT_S,
    RETURN_MAP_SKIP,
    AtlasOutput,
    Cell,
    CellResult,
    FinderConfig,
    FinderOutput,
    Probe,
    RunFailure,
    find,
    region_of,
    resolve_numerics,
    return_map_from_series,
)

FINDER_COLUMNS = ["beta", "body_mass_g", "slope_deg", "kind", "d31", "gait", "starts", "slope",
                  "drift"]  # fmt: skip
# Columns of each kind's `records`, so that an empty table still has its header.
RECORD_COLUMNS: dict[str, list[str]] = {
    "run": ["d31_init", "beta", "d31_final", "gait", "speed_cm_s", "duty_factor_measured",
            "slip_fraction", "landing_swing_share", "retouches_per_stance", "n_touchdowns"],
    "return_map": ["d31_init", "n", "d31_n", "d31_n_plus_lag"],
    "sweep": ["d31_init", "beta", "d31_final", "gait", "speed_cm_s", "duty_factor_measured",
              "slip_fraction", "landing_swing_share", "retouches_per_stance", "n_touchdowns"],
    "bifurcation": FINDER_COLUMNS,
    "atlas": [*FINDER_COLUMNS, "region"],
    "hysteresis": ["time_s", "leg", "value", "d31"],
}  # fmt: skip
# The time-series tables of a run job with include_series (`?table=` of the CSV export).
SERIES_COLUMNS: dict[str, list[str]] = {
    "d31": ["run", "d31_init", "n", "time_s", "d31"],
    "samples": ["run", "d31_init", "time_s", *(f"stance_{leg}" for leg in LEG_NAMES),
                "x_m", "y_m", "z_m"],
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


# what the insect did, per physical failure kind (sim_core.contract.FailureKind)
PHYSICAL_WORDS: dict[str, str] = {
    "flipped": "fell over",
    "on_floor": "fell over",
    "left_ground": "left the ground",
    "no_footholds": "lost every foothold",
    "sliding_back": "slid backwards",
}


def advice(job: _Physics, failures: list[RunFailure]) -> str:
    """What the client can do about failed runs, chosen from the failures' kinds: a smaller
    step only where the step is the likely cause (a numerical blow-up, or a step coarser than
    the converged default); a fall or flip at a sound step is the insect's physics under these
    conditions."""
    integrator, dt, _, _ = resolve_numerics(job.integrator, job.dt_s, job.control_dt_s)
    numerical = any(f.numerical for f in failures)
    if numerical or dt > DEFAULT_DT_S * (1 + 1e-9):
        return (
            f"the timestep is the likely cause ({integrator} at dt_s {dt:g} s): try a smaller "
            f"dt_s (the converged default is {DEFAULT_INTEGRATOR} at {DEFAULT_DT_S:g} s; "
            f"{integrator} is stable up to {MAX_STABLE_DT_S[integrator]:g} s)"
        )
    what = " or ".join(dict.fromkeys(PHYSICAL_WORDS.get(f.kind, "fell over") for f in failures))
    return (
        f"the insect {what} under these conditions (slope_deg {job.slope_deg:g}, "
        f"body_mass_g {job.body_mass_g:g}); this is the model's physics at a converged "
        "timestep, not a numerical problem, so a smaller dt_s will not help: change the "
        "conditions"
    )


def _failed(job: _Physics, failed: list[tuple[str, RunFailure]], total: int) -> JobFailed:
    """`failed`: (which run, its failure) for every run that stopped early."""
    return JobFailed(
        f"{len(failed)} of {total} simulation(s) failed, so the job returns no numbers; "
        f"{advice(job, [f for _, f in failed])}. "
        + "; ".join(f"{which}: {failure}" for which, failure in failed)
    )


def _batch(core: Any, job: RunJob | ReturnMapJob, progress: Progress, nthread: int) -> list[Any]:
    specs = [core.RunSpec(beta=job.beta, d31_init=d, **job.run_fields()) for d in job.d31_init]
    results: list[Any] = core.simulate_batch(specs, nthread=nthread, progress=progress)
    failed = [
        (f"run {i + 1} of {len(results)} (d31_init = {d:.4g})", r.failure)
        for i, (d, r) in enumerate(zip(job.d31_init, results, strict=True))
        if r.failure is not None
    ]
    if failed:
        raise _failed(job, failed, len(results))
    return results


SUMMARY_ONLY = ("d31", "error", "diverged", "failure", "warnings")  # not columns of a row


def _summary_row(d31_init: float, summary: dict[str, Any]) -> dict[str, Any]:
    row = {"d31_init": d31_init}
    row.update({k: v for k, v in summary.items() if k not in SUMMARY_ONLY})
    row["n_touchdowns"] = len(summary.get("d31") or [])
    return row


def run_job(job: RunJob, progress: Progress, nthread: int) -> dict[str, Any]:
    core = _core()
    results = _batch(core, job, progress, nthread)
    runs = [r.to_dict() if job.include_series else r.summary() for r in results]
    records = [_summary_row(d, r.summary()) for d, r in zip(job.d31_init, results, strict=True)]
    out: dict[str, Any] = {"kind": "run", "runs": runs, "records": records,
                           "warnings": _warnings(results)}  # fmt: skip
    if job.include_series:
        out["series"] = series_tables(job.d31_init, runs)
    return out


def _warnings(results: list[Any]) -> list[str]:
    """Every distinct warning of the job's runs (`RunResult.warnings`), in first-seen order:
    what the numbers say about themselves, e.g. a duty factor off beta at a coarse step."""
    return list(dict.fromkeys(w for r in results for w in r.warnings))


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
    """The paper's Fig. 7 construction, the core's own (`return_map_from_series`, as in
    `reproduce`): Delta31 at touchdown n against touchdown n + lag, the first
    RETURN_MAP_SKIP touchdowns of each run dropped; `n` counts from the run's first touchdown."""
    core = _core()
    results = _batch(core, job, progress, nthread)
    records: list[dict[str, Any]] = []
    for d0, res in zip(job.d31_init, results, strict=True):
        rm = return_map_from_series(job.beta, [res.d31], lag=job.lag)
        for k, (x, y) in enumerate(zip(rm.x.tolist(), rm.y.tolist(), strict=True)):
            records.append({"d31_init": d0, "n": RETURN_MAP_SKIP + k, "d31_n": x,
                            "d31_n_plus_lag": y})  # fmt: skip
    runs = [r.summary() for r in results]
    return {
        "kind": "return_map",
        "beta": job.beta,
        "lag": job.lag,
        "records": records,
        "runs": runs,
    }


def _grid(
    core: Any, job: SweepJob, progress: Progress, nthread: int
) -> list[tuple[float, float, Any]]:
    """Every (beta, d31_init) of the job's grid as independent runs, one batch call."""
    pairs = [(b, d) for b in job.beta_range.values() for d in job.d31_init]
    specs = core.spec_grid(job.beta_range.values(), job.d31_init, **job.run_fields())
    results = core.simulate_batch(specs, nthread=nthread, progress=progress)
    failed = [
        (f"beta {b:.4g}, d31_init {d:.4g}", r.failure)
        for (b, d), r in zip(pairs, results, strict=True)
        if r.failure is not None
    ]
    if failed:
        raise _failed(job, failed, len(results))
    return [(b, d, r) for (b, d), r in zip(pairs, results, strict=True)]


def sweep_job(job: SweepJob, progress: Progress, nthread: int) -> dict[str, Any]:
    """Final Delta31 and gait for every beta of the grid and every initial Delta31."""
    core = _core()
    records = []
    grid = _grid(core, job, progress, nthread)
    for beta, d0, res in grid:
        row = _summary_row(d0, res.summary())
        row["beta"] = beta
        records.append(row)
    return {"kind": "sweep", "records": records, "warnings": _warnings([r for _, _, r in grid])}


FinderRun = Callable[[list[tuple[Cell, Probe]]], list[dict[str, Any]]]


def _finder_runner(
    core: Any, job: BifurcationJob | AtlasJob, progress: Progress, nthread: int
) -> FinderRun:
    """The finder's `run`: each round as one `simulate_batch` (this worker's threads), with
    the job's numerics; progress as the share of the job's estimated simulated time done."""
    budget = max(job.total_sim_seconds(), 1e-9)
    done = 0.0

    def run(batch: list[tuple[Cell, Probe]]) -> list[dict[str, Any]]:
        nonlocal done
        specs = [
            core.RunSpec(d31_init=p.d31_init, duration_s=p.duration_s, **c.spec_fields(),
                         **job.numerics_fields())
            for c, p in batch
        ]  # fmt: skip
        results = core.simulate_batch(specs, nthread=nthread)
        done += sum(p.duration_s for _, p in batch)
        progress(min(0.99, done / budget))
        return [{"d31": r.d31.tolist(), "error": r.error} for r in results]

    return run


def _finder_rows(
    cells: list[CellResult], extra: dict[str, Any] | None = None
) -> list[dict[str, Any]]:
    """One row per point the finder reports: stable, unstable, ghost or not settled."""
    rows: list[dict[str, Any]] = []
    for c in cells:
        base = {"beta": c.beta, "body_mass_g": c.body_mass_g, "slope_deg": c.slope_deg}
        for a in c.attractors:
            rows.append(base | {"kind": "stable", "d31": a.d31, "gait": a.gait,
                                "starts": a.starts, "slope": a.slope,
                                "drift": a.max_drift})  # fmt: skip
        for b in c.borders:
            rows.append(base | {"kind": "unstable", "d31": b.d31, "gait": None, "starts": None,
                                "slope": b.slope, "drift": None})  # fmt: skip
        for g in c.ghosts:
            rows.append(base | {"kind": "ghost", "d31": g.d31, "gait": None, "starts": None,
                                "slope": None, "drift": g.drift})  # fmt: skip
        for u in c.unsettled:
            rows.append(base | {"kind": "not settled", "d31": u.final, "gait": None,
                                "starts": None, "slope": None, "drift": u.drift})  # fmt: skip
    return rows


def bifurcation_job(job: BifurcationJob, progress: Progress, nthread: int) -> dict[str, Any]:
    """Fig. 8 from settled walking: the fixed-point finder (`find`, the function `reproduce`
    uses) at every beta of the grid; its typed output (`FinderOutput`) plus flat rows."""
    core = _core()
    cells = [Cell(beta=b, body_mass_g=job.body_mass_g, slope_deg=job.slope_deg)
             for b in job.beta_range.values()]  # fmt: skip
    found = find(cells, job.finder_config(), _finder_runner(core, job, progress, nthread))
    out = FinderOutput(source="REST bifurcation job: the settled fixed-point finder",
                       config=asdict(job.finder_config()), cells=found)  # fmt: skip
    return {"kind": "bifurcation", "finder": out.model_dump(mode="json"),
            "records": _finder_rows(found)}  # fmt: skip


def atlas_job(job: AtlasJob, progress: Progress, nthread: int) -> dict[str, Any]:
    """The gait atlas on the job's grid: `atlas_search`, the function `insect-gait atlas`
    uses; its typed output (`AtlasOutput`) plus flat rows with each cell's region."""
    core = _core()
    cfg = core.AtlasConfig(job.axis, betas=tuple(job.betas), values=tuple(job.values),
                           finder=FinderConfig(starts=job.starts, duration_s=job.duration_s,
                                               max_borders=0))  # fmt: skip
    atlas: AtlasOutput = core.atlas_search(cfg, _finder_runner(core, job, progress, nthread))
    rows = _finder_rows(atlas.cells)
    regions = {(c.beta, c.body_mass_g, c.slope_deg): region_of(c) for c in atlas.cells}
    for r in rows:
        r["region"] = regions[(r["beta"], r["body_mass_g"], r["slope_deg"])]
    return {"kind": "atlas", "atlas": atlas.model_dump(mode="json"), "records": rows}


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
    if res.failure is not None:
        raise _failed(job, [("the sweep run", res.failure)], 1)
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
    "atlas": atlas_job,
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

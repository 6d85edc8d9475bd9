"""`run`: independent simulations at one beta, one per initial Delta31, optionally with their
time series (Delta31 per touchdown, stance per leg, body position) as two more tables."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

from pydantic import BaseModel, Field, create_model

import sim_core
from server.kinds.base import Kind, Result, Row, Timed
from server.kinds.bounds import D31, core_default, core_field, d31_list
from server.kinds.common import (
    RunRow,
    check_runs,
    d31_axis,
    summary_row,
    warnings_of,
)
from server.kinds.compute import Compute
from sim_core.contract import LEG_NAMES, RunRecord, RunSummary

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from server.kinds.return_map import ReturnMapJob


class D31Row(Row):
    """Delta31 at one leg-1 touchdown of one run (the `d31` table)."""

    run: int = Field(description="the run's index in the job")
    d31_init: float = Field(description="its initial Delta31, rad")
    n: int = Field(description="the touchdown's index in the run")
    time_s: float = Field(description="when, s")
    d31: float = Field(description="Delta31 just after it, rad")


_STANCE = {
    f"stance_{leg}": (int, Field(description=f"1: leg {leg} in stance")) for leg in LEG_NAMES
}
if TYPE_CHECKING:  # generated below (a stance column per leg); fields skipped by type checkers

    class SampleRow(Row):
        """One recorded sample of one run (the `samples` table)."""

else:
    SampleRow = create_model(
        "SampleRow",
        __base__=Row,
        __doc__="One recorded sample of one run (the `samples` table): stance per leg in the "
        "paper's order 1..6 = R1 L1 R2 L2 R3 L3, body position, m.",
        run=(int, Field(description="the run's index in the job")),
        d31_init=(float, Field(description="its initial Delta31, rad")),
        time_s=(float, Field(description="when, s")),
        **_STANCE,
        x_m=(float, Field(description="body position along the slope, m")),
        y_m=(float, Field(description="body position across the slope, m")),
        z_m=(float, Field(description="body height, m")),
    )
# The time-series tables of a run job with include_series (`?table=` of the CSV export).
SERIES_ROWS: dict[str, type[Row]] = {"d31": D31Row, "samples": SampleRow}


class RunJob(Timed):
    """Independent simulations at one beta, one per initial Delta31."""

    kind: Literal["run"] = "run"
    beta: float = core_field("beta")
    d31_init: list[D31] = d31_list([core_default("d31_init")])
    include_series: bool = Field(
        False, description="also keep each run's time series (large); for plots and CSV export"
    )

    def run_count(self) -> int:
        return len(self.d31_init)

    def keeps_series(self) -> bool:
        return self.include_series


def simulate_each(job: RunJob | ReturnMapJob, compute: Compute) -> list[dict[str, Any]]:
    """Each run's summary (`RunResult.summary`), one run per d31_init of a `run` or
    `return_map` job, every run a task through the shared cache; `JobFailed` naming every run
    that failed."""
    params = job.model_params()
    specs = [job.spec(beta=job.beta, d31_init=d, duration_s=job.duration_s) for d in job.d31_init]
    summaries = [sim_core.summary_of(r)
                 for r in compute.run([sim_core.run_task(s, params) for s in specs])]  # fmt: skip
    check_runs(job, run_labels(job), summaries)
    return summaries


def run_labels(job: RunJob | ReturnMapJob) -> list[str]:
    """Each run's name in a failure message."""
    n = len(job.d31_init)
    return [f"run {i + 1} of {n} (d31_init = {d:.4g})" for i, d in enumerate(job.d31_init)]


def simulate_with_series(job: RunJob, compute: Compute) -> list[sim_core.RunResult]:
    """Each run's result, with its time series, one batch call in this worker. Not through
    the cache: a task keeps a run's summary and events, not its sampled series (storing them
    would change what every cached task holds), so a job with include_series is computed each
    time, on this worker, and counted as computed."""
    specs = [job.spec(beta=job.beta, d31_init=d, duration_s=job.duration_s) for d in job.d31_init]
    results = sim_core.simulate_batch(specs, job.model_params(), nthread=compute.nthread,
                                      progress=compute.progress)  # fmt: skip
    compute.computed_elsewhere(len(specs))
    check_runs(job, run_labels(job), [r.summary() for r in results])
    return results


class SeriesTables(BaseModel):
    """A run job's time series as flat tables (SERIES_COLUMNS; the CSV export's `table`)."""

    d31: list[D31Row] = Field(description="Delta31 at every leg-1 touchdown of every run")
    samples: list[SampleRow] = Field(
        description="every recorded sample: stance per leg (paper order), body position, m"
    )


class RunJobResult(Result):
    """A run job's result."""

    kind: Literal["run"] = "run"
    records: list[RunRow]
    runs: list[RunSummary] | list[RunRecord] = Field(
        description="each run's summary (RunResult.summary: Delta31 at each touchdown, the "
        "final Delta31, gait, duty factor, speed, failure ...), or with include_series its "
        "whole record (RunResult.to_dict, with the sampled time series)"
    )
    warnings: list[str] = Field(description="what the runs' numbers say about themselves")
    series: SeriesTables | None = Field(None, description="with include_series only")


def run(job: RunJob, compute: Compute) -> RunJobResult:
    """Each run's summary (through the shared cache) or, with include_series, its whole
    record (computed here: `simulate_with_series`), and one summary row per run."""
    if job.include_series:
        results = simulate_with_series(job, compute)
        runs, summaries = [r.to_dict() for r in results], [r.summary() for r in results]
    else:
        runs = summaries = simulate_each(job, compute)
    records = [summary_row(d, r) for d, r in zip(job.d31_init, summaries, strict=True)]
    return RunJobResult(
        runs=runs,
        records=records,
        warnings=warnings_of(summaries),
        series=series_tables(job.d31_init, runs) if job.include_series else None,
    )


def series_tables(d31_init: list[float], runs: list[dict[str, Any]]) -> SeriesTables:
    """The time series as flat tables: Delta31 at each leg-1 touchdown, and every recorded
    sample (stance per leg in the paper's order 1..6 = R1 L1 R2 L2 R3 L3, as
    `LEG_NAMES` of `sim_core.contract`; body position, m)."""
    legs = list(_STANCE)
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
    return SeriesTables(d31=d31_rows, samples=samples)


def draw(fig: Figure, spec: dict[str, Any], result: dict[str, Any]) -> None:
    """Delta31 over touchdowns; with the time series, Delta31 over time, the footfall of the
    first run and the body's path, in three panels."""
    series = result.get("series") is not None
    if series:
        fig.set_size_inches(6.4, 9.6)
        ax, ax_foot, ax_pos = fig.subplots(3, 1)
    else:
        ax = fig.add_subplot()
    for d0, run in zip(spec.get("d31_init", []), result.get("runs", []), strict=False):
        d31 = run.get("d31") or []
        xs = run.get("d31_times_s") if series else range(len(d31))
        ax.plot(xs, d31, marker="o", ms=3, label=f"Δ31(0) = {d0:.2f}")
    ax.set_xlabel("time at leg-1 touchdown (s)" if series else "leg-1 touchdown n")
    ax.set_ylabel("Δ31 (rad)")
    d31_axis(ax)
    ax.set_title(f"run: β = {spec.get('beta')}, {spec.get('duration_s')} s")
    if 0 < len(result.get("runs", [])) <= 12:
        ax.legend(fontsize="small")
    if series:
        _footfall(ax_foot, result["runs"][0])
        _body_path(ax_pos, result["runs"])
    ax.grid(alpha=0.3)


STANCE_WINDOW_S = 1.0  # the stance panel's span: ~6 gait cycles, each bar still a bar


def _footfall(ax: Axes, run: dict[str, Any]) -> None:
    """Stance bars per leg (first run), paper legs 1..6 from the top, over the run's last
    STANCE_WINDOW_S: a whole 10 s run's ~60 cycles drew solid bars."""
    times = run.get("times_s") or []
    stance = run.get("stance") or []
    span = f"last {STANCE_WINDOW_S:g} s" if times and times[-1] - times[0] > STANCE_WINDOW_S else ""
    ax.set_title(f"stance (first run{', ' + span if span else ''})")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("leg")
    if len(times) < 2:
        return
    dt = times[1] - times[0]
    since = times[-1] - STANCE_WINDOW_S
    for leg in range(6):
        spans: list[tuple[float, float]] = []
        for t, row in zip(times, stance, strict=False):
            if row[leg] and t >= since:
                if spans and abs(spans[-1][0] + spans[-1][1] - t) < 1.5 * dt:
                    spans[-1] = (spans[-1][0], spans[-1][1] + dt)
                else:
                    spans.append((t, dt))
        ax.broken_barh(spans, (5 - leg - 0.4, 0.8), color="black")
    ax.set_yticks(range(6), list(LEG_NAMES)[::-1])
    ax.set_xlim(max(times[0], since), times[-1])


def _body_path(ax: Axes, runs: list[dict[str, Any]]) -> None:
    for k, run in enumerate(runs[:12]):
        pos = run.get("body_pos_m") or []
        ax.plot(run.get("times_s") or [], [100.0 * p[0] for p in pos], label=f"run {k}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("body x (cm)")
    ax.set_title("body position along the slope")


KIND = Kind(model=RunJob, run=run, result=RunJobResult, row=RunRow, draw=draw, tables=SERIES_ROWS)

"""`sweep`: final gait and Delta31 over a beta grid for each initial Delta31 (paper Figs. 5-6),
every grid point an independent run."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field

import sim_core
from server.kinds.base import BetaRange, Kind, Result, Timed
from server.kinds.bounds import D31, core_default, d31_list
from server.kinds.common import (
    RunRow,
    check_runs,
    conditions,
    d31_axis,
    paper_transitions,
    summary_row,
    warnings_of,
)
from server.kinds.compute import Compute

if TYPE_CHECKING:
    from matplotlib.figure import Figure


class SweepJob(Timed):
    """Final gait and Delta31 over a beta grid for each initial Delta31 (paper Figs. 5-6)."""

    kind: Literal["sweep"] = "sweep"
    beta_range: BetaRange
    d31_init: list[D31] = d31_list([core_default("d31_init")])

    def run_count(self) -> int:
        return len(self.d31_init) * self.beta_range.steps


def _grid(job: SweepJob, compute: Compute) -> list[tuple[float, float, dict[str, Any]]]:
    """Every (beta, d31_init) of the job's grid as independent runs, each a task through the
    shared cache: (beta, d31_init, the run's summary)."""
    pairs = [(b, d) for b in job.beta_range.values() for d in job.d31_init]
    specs = sim_core.spec_grid(job.beta_range.values(), job.d31_init,
                               **dict(job.template()), duration_s=job.duration_s)  # fmt: skip
    params = job.model_params()
    summaries = [sim_core.summary_of(r)
                 for r in compute.run([sim_core.run_task(s, params) for s in specs])]  # fmt: skip
    check_runs(job, [f"beta {b:.4g}, d31_init {d:.4g}" for b, d in pairs], summaries)
    return [(b, d, s) for (b, d), s in zip(pairs, summaries, strict=True)]


class SweepJobResult(Result):
    """A sweep job's result: one summary row per (beta, initial Delta31)."""

    kind: Literal["sweep"] = "sweep"
    records: list[RunRow]
    warnings: list[str] = Field(description="what the runs' numbers say about themselves")


def run(job: SweepJob, compute: Compute) -> SweepJobResult:
    """Final Delta31 and gait for every beta of the grid and every initial Delta31."""
    records = []
    grid = _grid(job, compute)
    for beta, d0, summary in grid:
        row = summary_row(d0, summary)
        row["beta"] = beta
        records.append(row)
    return SweepJobResult(records=records, warnings=warnings_of([s for _, _, s in grid]))


def draw(fig: Figure, spec: dict[str, Any], result: dict[str, Any]) -> None:
    """Final Delta31 against beta, every run of the grid."""
    ax = fig.add_subplot()
    records = result.get("records", [])
    pts = [(r["beta"], r["d31_final"]) for r in records if r.get("d31_final") is not None]
    ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=6)
    paper_transitions(ax)
    ax.set_xlabel("duty factor β")
    ax.set_ylabel("final Δ31 (rad)")
    d31_axis(ax)
    ax.set_title(f"sweep: final Δ31 over β{conditions(spec)}", fontsize="medium")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)


KIND = Kind(model=SweepJob, run=run, result=SweepJobResult, row=RunRow, draw=draw)

"""`return_map`: the paper's Fig. 7, pairs (Delta31[n], Delta31[n + lag]) collected over
several runs at one beta."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field

from server.kinds.base import Kind, Result, Row, Timed
from server.kinds.bounds import (
    D31,
    TWO_PI,
    IntLike,
    bounded,
    core_field,
    d31_list,
)
from server.kinds.common import d31_axis
from server.kinds.compute import Compute
from server.kinds.run import simulate_each
from sim_core import return_map_from_series
from sim_core.contract import RETURN_MAP_SKIP, RunSummary

if TYPE_CHECKING:
    from matplotlib.figure import Figure


class ReturnMapRow(Row):
    """One pair of the return map."""

    d31_init: float = Field(description="the run's initial Delta31, rad")
    n: int = Field(description="the first member's touchdown, counted from the run's first")
    d31_n: float = Field(description="Delta31 at touchdown n, rad")
    d31_n_plus_lag: float = Field(description="Delta31 at touchdown n + lag, rad")


class ReturnMapJob(Timed):
    """Fig. 7 of the paper: pairs (Delta31[n], Delta31[n + lag]) collected over several runs."""

    kind: Literal["return_map"] = "return_map"
    beta: float = core_field("beta")
    d31_init: list[D31] = d31_list([TWO_PI * i / 12.0 for i in range(12)])
    lag: IntLike = bounded(4, "lag", "touchdowns between the two members of a pair", ge=1, le=50)

    def run_count(self) -> int:
        return len(self.d31_init)


class ReturnMapJobResult(Result):
    """A return_map job's result: the pairs as records, with each run's summary."""

    kind: Literal["return_map"] = "return_map"
    records: list[ReturnMapRow]
    beta: float = Field(description="the duty factor of every run")
    lag: int = Field(description="touchdowns between the two members of a pair")
    runs: list[RunSummary] = Field(description="each run's summary (RunResult.summary)")


def run(job: ReturnMapJob, compute: Compute) -> ReturnMapJobResult:
    """The paper's Fig. 7 construction, the core's own (`return_map_from_series`, as in
    `reproduce`): Delta31 at touchdown n against touchdown n + lag, the first
    RETURN_MAP_SKIP touchdowns of each run dropped; `n` counts from the run's first touchdown.
    The runs go through the shared cache (`simulate_each`)."""
    runs = simulate_each(job, compute)
    records: list[dict[str, Any]] = []
    for d0, summary in zip(job.d31_init, runs, strict=True):
        rm = return_map_from_series(job.beta, [summary["d31"]], lag=job.lag)
        for k, (x, y) in enumerate(zip(rm.x.tolist(), rm.y.tolist(), strict=True)):
            records.append({"d31_init": d0, "n": RETURN_MAP_SKIP + k, "d31_n": x,
                            "d31_n_plus_lag": y})  # fmt: skip
    return ReturnMapJobResult(beta=job.beta, lag=job.lag, records=records, runs=runs)


def draw(fig: Figure, spec: dict[str, Any], result: dict[str, Any]) -> None:
    """The return map: Delta31[n + lag] against Delta31[n], with the diagonal."""
    ax = fig.add_subplot()
    records = result.get("records", [])
    xs = [r["d31_n"] for r in records]
    ys = [r["d31_n_plus_lag"] for r in records]
    ax.scatter(xs, ys, s=8)
    ax.plot([0, TWO_PI], [0, TWO_PI], color="grey", lw=0.8)
    lag = result.get("lag", spec.get("lag"))
    ax.set_xlabel("Δ31[n] (rad)")
    ax.set_ylabel(f"Δ31[n+{lag}] (rad)")
    d31_axis(ax, "x")
    d31_axis(ax)
    ax.set_title(f"return map: β = {spec.get('beta')}")
    ax.grid(alpha=0.3)


KIND = Kind(model=ReturnMapJob, run=run, result=ReturnMapJobResult, row=ReturnMapRow, draw=draw)

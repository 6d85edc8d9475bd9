"""What the kinds' runners and figures share: the failure message and its advice, a run's
summary row, and the Delta31 axis.

Runs only inside worker processes (runners) or request threads (figures); importing it loads
neither MuJoCo nor matplotlib.
"""

from __future__ import annotations

import math
from dataclasses import fields
from typing import TYPE_CHECKING, Any

from server.kinds.base import JobFailed, Physics
from server.kinds.bounds import TWO_PI
from sim_core.contract import (
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    INSECT_WORDS,
    MAX_STABLE_DT_S,
    Integrator,
    RunFailure,
    RunMeasures,
    resolve_numerics,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes

SUMMARY_ONLY = ("d31", "error", "diverged", "failure", "warnings")  # not columns of a row
# Columns of a run's summary row (`summary_row`): the run and sweep kinds' records, i.e. the
# start, beta and every measure of `RunResult.summary` (read from `RunMeasures`' fields)
SUMMARY_COLUMNS = (
    "d31_init",
    "beta",
    *(f.name for f in fields(RunMeasures) if f.name not in SUMMARY_ONLY),
    "n_touchdowns",
)


def advice(job: Physics, failures: list[RunFailure]) -> str:
    """What the client can do about failed runs, chosen from the failures' kinds: a smaller
    step only where the step is the likely cause (a numerical blow-up, or a step coarser than
    the converged default); a fall or flip at a sound step is the insect's physics under these
    conditions."""
    integrator: Integrator = job.integrator or DEFAULT_INTEGRATOR
    dt = resolve_numerics(integrator, job.dt_s, job.control_dt_s)[1]
    numerical = any(f.numerical for f in failures)
    if numerical or dt > DEFAULT_DT_S * (1 + 1e-9):
        return (
            f"the timestep is the likely cause ({integrator} at dt_s {dt:g} s): try a smaller "
            f"dt_s (the converged default is {DEFAULT_INTEGRATOR} at {DEFAULT_DT_S:g} s; "
            f"{integrator} is stable up to {MAX_STABLE_DT_S[integrator]:g} s)"
        )
    what = " or ".join(dict.fromkeys(INSECT_WORDS.get(f.kind, "fell over") for f in failures))
    return (
        f"the insect {what} under these conditions (slope_deg {job.slope_deg:g}, "
        f"body_mass_g {job.body_mass_g:g}); this is the model's physics at a converged "
        "timestep, not a numerical problem, so a smaller dt_s will not help: change the "
        "conditions"
    )


def failed(job: Physics, failures: list[tuple[str, RunFailure]], total: int) -> JobFailed:
    """The job's failure; `failures`: (which run, its failure) for every run that stopped
    early."""
    return JobFailed(
        f"{len(failures)} of {total} simulation(s) failed, so the job returns no numbers; "
        f"{advice(job, [f for _, f in failures])}. "
        + "; ".join(f"{which}: {failure}" for which, failure in failures)
    )


def summary_row(d31_init: float, summary: dict[str, Any]) -> dict[str, Any]:
    """One run's summary as a flat row (SUMMARY_COLUMNS)."""
    row = {"d31_init": d31_init}
    row.update({k: v for k, v in summary.items() if k not in SUMMARY_ONLY})
    row["n_touchdowns"] = len(summary.get("d31") or [])
    return row


def warnings_of(results: list[Any]) -> list[str]:
    """Every distinct warning of the job's runs (`RunMeasures.warnings`), in first-seen order:
    what the numbers say about themselves, e.g. a duty factor off beta at a coarse step."""
    return list(dict.fromkeys(w for r in results for w in r.measures.warnings))


def d31_axis(ax: Axes, axis: str = "y") -> None:
    """Delta31 from 0 to 2 pi on `ax`'s y (or x) axis, ticked at multiples of pi / 2."""
    ticks = [0, math.pi / 2, math.pi, 3 * math.pi / 2, TWO_PI]
    labels = ["0", "π/2", "π", "3π/2", "2π"]
    if axis == "y":
        ax.set_ylim(0, TWO_PI)
        ax.set_yticks(ticks, labels)
    else:
        ax.set_xlim(0, TWO_PI)
        ax.set_xticks(ticks, labels)

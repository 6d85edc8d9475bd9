"""What the kinds' runners and figures share: the failure message and its advice, a run's
summary row, the Delta31 axis and the paper's numbers beside ours.

Runs only inside worker processes (runners) or request threads (figures); importing it loads
neither MuJoCo nor matplotlib.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from pydantic import Field, create_model

from server.kinds.base import JobFailed, Physics, Row
from server.kinds.bounds import TWO_PI
from sim_core.contract import (
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    INSECT_WORDS,
    MAX_STABLE_DT_S,
    PAPER,
    Integrator,
    RunFailure,
    RunSummary,
    resolve_numerics,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes

SUMMARY_ONLY = ("d31", "error", "diverged", "failure", "warnings")  # not columns of a row

# A run's summary row (`summary_row`), the run and sweep kinds' records: the start, beta and
# every measure of the core's `RunSummary` (so of `RunMeasures`: a new measure is a new
# column with no edit here), and the touchdowns counted.
if TYPE_CHECKING:  # generated below; type checkers see a row model whose fields they skip

    class RunRow(Row):
        """One run's summary as a flat row."""

else:
    RunRow = create_model(
        "RunRow",
        __base__=Row,
        __doc__="One run's summary as a flat row: its start, beta and every measure.",
        d31_init=(float, Field(description="the run's initial Delta31, rad")),
        **{n: (f.annotation, f) for n, f in RunSummary.model_fields.items()
           if n not in SUMMARY_ONLY},
        n_touchdowns=(int, Field(description="leg-1 touchdowns, so Delta31 samples")),
    )  # fmt: skip
SUMMARY_COLUMNS = tuple(RunRow.model_fields)


def advice(job: Physics, failures: list[RunFailure]) -> str:
    """What the client can do about failed runs, chosen from the failures' kinds: a smaller
    step only where the step is the likely cause (a numerical blow-up, or a step coarser than
    the converged default); a fall or flip at a sound step is the insect's physics under these
    conditions."""
    held = job.spec()  # the job's template, typed
    integrator: Integrator = held.integrator or DEFAULT_INTEGRATOR
    dt = resolve_numerics(integrator, held.dt_s, held.control_dt_s)[1]
    numerical = any(f.numerical for f in failures)
    if numerical or dt > DEFAULT_DT_S * (1 + 1e-9):
        return (
            f"the timestep is the likely cause ({integrator} at dt_s {dt:g} s): try a smaller "
            f"dt_s (the converged default is {DEFAULT_INTEGRATOR} at {DEFAULT_DT_S:g} s; "
            f"{integrator} is stable up to {MAX_STABLE_DT_S[integrator]:g} s)"
        )
    what = " or ".join(dict.fromkeys(INSECT_WORDS.get(f.kind, "fell over") for f in failures))
    return (
        f"the insect {what} under these conditions (slope_deg {held.slope_deg:g}, "
        f"body_mass_g {held.body_mass_g:g}); this is the model's physics at a converged "
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


def check_runs(job: Physics, labels: list[str], summaries: list[dict[str, Any]]) -> None:
    """Raise the job's failure (`failed`) if any run stopped early: `labels` name the runs,
    `summaries` are their summaries (`RunResult.summary`, whose `failure` is a dict)."""
    failures = [
        (label, RunFailure(**s["failure"]))
        for label, s in zip(labels, summaries, strict=True)
        if s.get("failure")
    ]
    if failures:
        raise failed(job, failures, len(summaries))


def summary_row(d31_init: float, summary: dict[str, Any]) -> dict[str, Any]:
    """One run's summary as a flat row (SUMMARY_COLUMNS)."""
    row = {"d31_init": d31_init}
    row.update({k: v for k, v in summary.items() if k not in SUMMARY_ONLY})
    row["n_touchdowns"] = len(summary.get("d31") or [])
    return row


def warnings_of(summaries: list[dict[str, Any]]) -> list[str]:
    """Every distinct warning of the job's runs (their summaries' `warnings`, from
    `RunMeasures`), in first-seen order: what the numbers say about themselves, e.g. a duty
    factor off beta at a coarse step."""
    return list(dict.fromkeys(w for s in summaries for w in s.get("warnings") or ()))


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


PAPER_COLOURS = {"tripod": "tab:orange", "metachronal": "tab:green"}


def conditions(spec: dict[str, Any]) -> str:
    """The walk's conditions a job ran under, for a figure's title: " (3 g, slope 0°, ground
    constraint)", or "" when the spec names none."""
    words = [
        fmt.format(spec[key])
        for key, fmt in (("body_mass_g", "{:g} g"), ("slope_deg", "slope {:g}°"),
                         ("ground", "ground {}"))
        if spec.get(key) is not None
    ]  # fmt: skip
    return f" ({', '.join(words)})" if words else ""


def paper_transitions(ax: Axes) -> None:
    """The paper's transition betas (Fig. 6a: metachronal -> tripod at 0.645 as beta falls,
    back at 0.67 as it rises) as dashed verticals, one legend entry naming them the paper's;
    the values are the core's `PAPER`, never retyped."""
    down, up = PAPER.transition_down, PAPER.transition_up
    label = f"paper: transitions β {down:g} ↓, {up:g} ↑"
    for beta in (down, up):
        ax.axvline(beta, ls=(0, (2, 2)), color="0.35", lw=0.9, label=label if beta == down else "")


def paper_ranges(ax: Axes) -> None:
    """The paper's Fig. 8: each gait's stable range of beta as a pale band at its branch value
    (Fig. 5), beside the finder's states."""
    for gait, (lo, hi), d31 in (
        ("tripod", PAPER.tripod_stable, PAPER.branch_tripod_rad),
        ("metachronal", PAPER.metachronal_stable, PAPER.branch_metachronal_rad),
    ):
        ax.hlines(d31, lo, hi, lw=7, alpha=0.3, color=PAPER_COLOURS[gait],
                  label=f"paper, Fig. 8: {gait} stable")  # fmt: skip

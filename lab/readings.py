"""Issue 31, step 2: the structural audit's other readings of the paper's text, screened.

Every setting tried over three campaigns leaves a metachronal-side state at beta 0.62; the audit
(docs/studies/journal.md, tenth study) lists where the text permits another reading than ours.
Each reading that can be built is a `ModelParams` option (default: our reading, bit-identical).
`screen` runs a reading on a ground from `STARTS` starts spread over the circle at each beta for
`duration_s`, and reports where the settled runs end (clustered as the fixed-point finder does),
each state's gait, the runs that did not settle, and the median landing share and slip: does the
metachronal-side state at 0.62 go (the fold the issue needs) while the tripod stays, and the
metachronal gait stay at 0.70? A lever can be screened under a reading (`over`), and a
census's claim checked with the reproduction's own instrument, the settled fixed-point finder
(`find_states`), and its robustness read by a census of each calibrated parameter at +-10% of
the setting's value (`variants`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim_core import Backend, ModelParams, ResultCache, RunSpec, find, run_task, run_tasks
from sim_core.contract import (
    GROUND_ONLY,
    Cell,
    CellResult,
    FinderConfig,
    classify_gait,
    settling,
)
from sim_core.research import (
    CALIBRATED,
    SCALES,
    cluster_finals,
    initial_values,
    scaled_values,
    task_runner,
)

# Each built reading: its name and the ModelParams fields that switch it on.
READINGS: dict[str, dict[str, Any]] = {
    "ours": {},
    # "The swing phase ... continues until the leg touches the ground": past the AEP the swing
    # target keeps reaching down (at the swing curve's final descent speed) instead of
    # following the AEP-PEP line
    "late descent": {"late_swing_descent": 1.0},
    # "The stance phase is a straight line from the landing position (LP) to the PEP": LP as
    # the tip's place at touchdown with its height, not only its fore-aft place on the line
    "landing height kept": {"landing_height_kept": 1.0},
    # "The line segment between the AEP and the PEP is parallel to the body": the trajectories
    # in the level frame of the heading, so that the body's pitch and roll move no target
    "level frame": {"trajectory_frame": "level"},
    # "the leg tips" touch the ground: a point, not our 0.25 mm sphere; a 0.05 mm sphere with
    # the contact's impedance width kept at 0.1 mm (solimp width is a share of the radius)
    "point foot": {"foot_radius": 0.05e-3, "contact_width_share": 2.0},
}
STARTS = 8  # the acceptance: "every one of 8 starts over the circle"


@dataclass(frozen=True)
class Census:
    """Where the runs of one reading, ground and beta ended."""

    reading: str
    ground: str
    beta: float
    states: list[tuple[float, int, str]]  # (settled Delta31, runs, gait)
    unsettled: list[float | None]  # where the runs that did not settle were last
    failed: int
    landing: float | None  # median landing share over the runs
    slip: float | None  # median slip share of the stroke


def screen(
    reading: str,
    ground: str,
    betas: Sequence[float],
    cache: ResultCache,
    backend: Backend,
    *,
    duration_s: float = 40.0,
    stop_if_settled_s: float | None = None,
    over: dict[str, Any] | None = None,
    starts: int = STARTS,
    progress: bool = True,
) -> list[Census]:
    """The census of `reading` on `ground` at each beta (see the module docstring); the runs go
    through the result cache on `backend`, so a repeated screen reads them back.

    over: further ModelParams values on top of the reading's (a lever screened under it; the
    census is then named after both). stop_if_settled_s: a run that has settled by then stops
    there (`RunSpec.stop_if_settled_s`): a cheaper screen, whose early verdicts can include a
    ghost that a 40 s run leaves (why the finder runs 40 s)."""
    p = setting(reading, ground, over)
    name = settings_name(reading, over)
    x0 = [float(x) for x in initial_values(starts)]
    specs = [
        RunSpec(beta=b, d31_init=x, duration_s=duration_s, stop_if_settled_s=stop_if_settled_s)
        for b in betas
        for x in x0
    ]
    tasks = [run_task(s, p) for s in specs]
    results, _ = run_tasks(tasks, cache, backend, chunk_size=4, progress=progress)
    done = [results[t.key] for t in tasks]
    out = []
    for k, b in enumerate(betas):
        rs = done[k * starts : (k + 1) * starts]
        ok = [r for r in rs if r["error"] is None]
        sts = [settling(r["d31"]) for r in ok]
        finals = [s.final for s in sts if s.settled and s.final is not None]
        states = [(v, n, classify_gait(v, b)) for v, n in cluster_finals(finals)]
        land = [r["landing_swing_share"] for r in ok if r["landing_swing_share"] is not None]
        slip = [r["slip_fraction"] for r in ok if r["slip_fraction"] is not None]
        out.append(Census(name, ground, b, states,
                          [s.final for s in sts if not s.settled], len(rs) - len(ok),
                          float(np.median(land)) if land else None,
                          float(np.median(slip)) if slip else None))  # fmt: skip
    return out


def table(rows: Sequence[Census]) -> list[str]:
    """A markdown table of censuses."""
    out = [
        "| reading | ground | β | settled states (runs, gait) | not settled (last at) | failed "
        "| landing | slip |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for c in rows:
        st = ", ".join(f"{v:.3f} ({n}, {g})" for v, n, g in c.states) or "none"
        un = ", ".join("–" if u is None else f"{u:.2f}" for u in c.unsettled) or "0"
        land = "–" if c.landing is None else f"{c.landing:.3f}"
        slip = "–" if c.slip is None else f"{100 * c.slip:.1f}%"
        out.append(f"| {c.reading} | {c.ground} | {c.beta:g} | {st} | {un} | {c.failed} | "
                   f"{land} | {slip} |")  # fmt: skip
    return out


def setting(reading: str, ground: str, over: dict[str, Any] | None) -> ModelParams:
    """The model of a reading on a ground with a lever's values on top."""
    if reading not in READINGS:
        raise ValueError(f"unknown reading {reading!r}; choose from {list(READINGS)}")
    # a reading's constant of the other ground never acted on this one (the point foot's
    # solimp width on the paper's ground): left out, as the model refuses it
    other = set().union(*(names for g, names in GROUND_ONLY.items() if g != ground))
    leaves = {k: v for k, v in READINGS[reading].items() if k not in other}
    return ModelParams.of(**{"ground": ground, **leaves, **(over or {})})


def settings_name(reading: str, over: dict[str, Any] | None) -> str:
    """A reading's name with the lever values screened under it."""
    return reading + "".join(
        f", {k} {v:g}" if isinstance(v, float) else f", {k} {v}" for k, v in (over or {}).items()
    )


def find_states(
    reading: str,
    ground: str,
    betas: Sequence[float],
    cache: ResultCache,
    backend: Backend,
    *,
    over: dict[str, Any] | None = None,
    cfg: FinderConfig | None = None,
    progress: bool = True,
) -> list[CellResult]:
    """The settled fixed-point finder (the reproduction's instrument: starts, kicks, bisected
    borders, neighbours' seeds) on one reading and ground at each beta: a census's claim
    about a fold checked with the instrument that reads Fig. 8."""
    p = setting(reading, ground, over)
    run = task_runner(cache, backend, p, progress=progress)
    return find([Cell(b) for b in betas], cfg or FinderConfig(), run)


def finder_table(name: str, ground: str, cells: Sequence[CellResult]) -> list[str]:
    """A markdown table of the finder's answer per beta (stable = kicks came back from both
    sides; the unstable borders by bisection; failed and unsettled runs counted)."""
    out = [
        "| setting | ground | β | stable states (starts, gait) | other settled states (kicks) "
        "| borders | not settled | failed |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for c in cells:
        st = ", ".join(f"{a.d31:.3f} ({a.starts}, {a.gait})" for a in c.stable()) or "none"
        ot = ", ".join(f"{a.d31:.3f} ({a.confirmed})" for a in c.one_sided()) or "none"
        bo = ", ".join("?" if b.d31 is None else f"{b.d31:.3f}" for b in c.borders) or "none"
        failed = sum(1 for r in c.runs if r.failure is not None)
        out.append(f"| {name} | {ground} | {c.beta:g} | {st} | {ot} | {bo} | "
                   f"{len(c.unsettled)} | {failed} |")  # fmt: skip
    return out


def variants(
    reading: str,
    ground: str,
    over: dict[str, Any] | None,
    names: Sequence[str] = CALIBRATED,
    scales: Sequence[float] = SCALES,
) -> list[dict[str, Any]]:
    """The lever values of the setting itself, then of each calibrated parameter at each scale
    of the setting's own value (the guide's +-10% check of a structure): a census of each
    says whether the same states live and how far a fold moves."""
    base = setting(reading, ground, over)
    return [dict(over or {})] + [{**(over or {}), **u} for _, u in
                                 scaled_values(base, names, scales)]  # fmt: skip

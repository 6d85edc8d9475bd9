"""What a calibration scores: three objectives over closed-loop or open-loop runs.

- closed-loop (`Evaluation`, `evaluate`): settled Delta31 of many runs at the paper's betas;
  an unsettled run counts as pi away;
- drift (`drift_score`): the sign of the open-loop drift around the paper's branches, a
  smoother and ~5x cheaper signal (its winners still need the closed-loop check);
- pull (`PullEvaluation`, `evaluate_pull`): how close short closed-loop runs end to the
  branches, with walking-sanity penalties.

branches, with walking sanity as hard-to-ignore penalties (fifth study, docs/studies/journal.md).

`calibration.Evaluation.score` counts a run that has not settled as pi away, so nearly every
candidate of a wide search scores the same and the sampler learns little; it also costs ~60 s a
candidate (three betas, half-step check). Here each run contributes exp(-(d / 0.3 rad)^2), d
its final Delta31's distance to the paper's branch at its beta, so a run moving toward the
branch already counts; one candidate is 2 betas x n starts x a few seconds (~10 s on 2 cores).
Winners still need the full check (`calibration.evaluate` at dt and dt/2, more starts, 0.655).

The penalties keep the search inside walking that is physically sane, the checks the fourth
study added after soft springs gave paper-like numbers for the wrong reason: feet must land in
the last fifth of the swing (not when the scuff window closes), slip little and walk at the
eq. 2 speed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from lab.space import SEARCH_SPACE
from sim_core import ModelParams, nominal_speed, simulate_batch, spec_grid
from sim_core.contract import TWO_PI, final_d31
from sim_core.research import (
    BETA_BISTABLE,
    BETA_FAST,
    BETA_SLOW,
    METACHRONAL_BRANCH,
    TRIPOD_BRANCH,
    angle_diff,
    initial_values,
    open_loop_drift,
    window_d31,
)

# rad of score per unit of speed error or slip beyond 10%: walking properly (the sim_core
# acceptance) outranks a closer Delta31 (0.1 of excess slip costs as much as 3 rad of Delta31)
WALK_PENALTY = 30.0


@dataclass
class Evaluation:
    """Closed-loop outcomes of one candidate: final Delta31 per beta and initial value."""

    params: dict[str, float]
    finals: dict[float, list[float | None]]  # None: diverged or unsettled
    speed_error: float  # worst relative speed error against eq. 2 among settled runs
    max_slip: float
    diverged: int

    def score(self) -> float:
        """Lower is better; 0 would be every run on the paper's branch at 0.62 and 0.70."""
        total = 0.0
        for beta, target in ((BETA_FAST, TRIPOD_BRANCH), (BETA_SLOW, METACHRONAL_BRANCH)):
            for f in self.finals.get(beta, []):
                total += math.pi if f is None else abs(float(angle_diff(f, target)))
        bis = [f for f in self.finals.get(BETA_BISTABLE, []) if f is not None]
        if bis:  # both branches reached from some initial value
            total += min(abs(float(angle_diff(f, TRIPOD_BRANCH))) for f in bis)
            total += min(abs(float(angle_diff(f, METACHRONAL_BRANCH))) for f in bis)
        else:
            total += TWO_PI
        total += WALK_PENALTY * max(0.0, self.speed_error - 0.10)
        total += WALK_PENALTY * max(0.0, self.max_slip - 0.10)
        return total


def evaluate(
    params: ModelParams,
    *,
    betas: Sequence[float] = (BETA_FAST, BETA_BISTABLE, BETA_SLOW),
    n_init: int = 8,
    duration_s: float = 6.0,
    dt_s: float | None = None,
    nthread: int = 0,
) -> Evaluation:
    specs = spec_grid(betas, initial_values(n_init), duration_s=duration_s, dt_s=dt_s)
    results = simulate_batch(specs, params, nthread=nthread)
    finals: dict[float, list[float | None]] = {b: [] for b in betas}
    speed_err = 0.0
    slip = 0.0
    diverged = 0
    for spec, res in zip(specs, results, strict=True):
        if res.diverged:
            diverged += 1
            finals[spec.beta].append(None)
            continue
        finals[spec.beta].append(window_d31(res.events.d31))  # a screen of short runs
        v = (
            nominal_speed(spec.beta, params.trajectory.stroke, params.trajectory.swing_duration)
            * 100
        )
        if res.measures.speed_cm_s is not None:
            speed_err = max(speed_err, abs(res.measures.speed_cm_s - v) / v)
        if res.measures.slip_fraction is not None:
            slip = max(slip, res.measures.slip_fraction)
    return Evaluation(
        params={k: params.leaf(k) for k in SEARCH_SPACE},
        finals=finals,
        speed_error=speed_err,
        max_slip=slip,
        diverged=diverged,
    )


def outcome_gap(a: Evaluation, b: Evaluation) -> float:
    """Sum over runs of the Delta31 outcome difference between two evaluations (pi if only
    one of them settled)."""
    gap = 0.0
    for beta, fa in a.finals.items():
        for x, y in zip(fa, b.finals.get(beta, []), strict=False):
            if x is None and y is None:
                continue
            gap += math.pi if x is None or y is None else abs(float(angle_diff(x, y)))
    return gap


DRIFT_GRID = np.linspace(0.0, TWO_PI, 18, endpoint=False) + math.pi / 18
DRIFT_SCALE = 0.01  # rad per cycle: a drift this size counts as a clear push (tanh ~ 0.76)


def drift_score(
    params: ModelParams,
    targets: dict[float, float] | None = None,
    duration_s: float = 1.5,
) -> dict[float, float]:
    """How well the open-loop drift points at the paper's branch, per beta, in [-1, 1].

    For each grid point more than 0.15 rad from the target branch, tanh(s d / 0.01) where d is
    `open_loop_drift` and s = +1 if the target lies ahead (the short way round), -1 if behind;
    1 means every point is pushed toward the branch, which then is the only attractor.
    """
    targets = targets or {BETA_FAST: TRIPOD_BRANCH, BETA_SLOW: METACHRONAL_BRANCH}
    out: dict[float, float] = {}
    for beta, target in targets.items():
        drift, _ = open_loop_drift(params, betas=[beta], d31s=DRIFT_GRID.tolist(),
                                   duration_s=duration_s, settle_s=duration_s / 3)  # fmt: skip
        d = drift[0]
        sign = np.sign(angle_diff(target, DRIFT_GRID))
        weight = (np.abs(angle_diff(target, DRIFT_GRID)) > 0.15).astype(float)
        push = np.where(np.isnan(d), -1.0, np.tanh(sign * d / DRIFT_SCALE))
        out[beta] = float(np.sum(weight * push) / weight.sum())
    return out


TARGETS: dict[float, float] = {BETA_FAST: TRIPOD_BRANCH, BETA_SLOW: METACHRONAL_BRANCH}
# between the two, some starts should reach each branch (Figs. 7, 8: both stable 0.645-0.67)
WIDTH = 0.3  # rad: a run ending this far from the branch counts 1/e
MIN_LANDING_SHARE = 0.8  # feet land after 80% of the swing
MAX_SLIP = 0.05  # of the stroke per stance
MAX_SPEED_ERROR = 0.10  # relative to eq. 2
PENALTY = 2.0  # per unit beyond each limit: 0.1 of excess slip costs 0.2, a fifth of the range


@dataclass
class PullEvaluation:
    """Per beta: final Delta31 of every run (None: diverged), and the walking checks."""

    finals: dict[float, list[float | None]]
    landing_share: dict[float, float | None]
    slip: dict[float, float | None]
    speed_error: dict[float, float | None]
    details: dict[str, float] = field(default_factory=dict)

    def closeness(self) -> float:
        """1 = the paper: every run at 0.62 and 0.70 on its branch (exp(-(d/WIDTH)^2) per run,
        averaged per beta) and, where a bistable beta was run, its nearest run to each branch
        on that branch; the betas weigh equally."""
        parts = []
        for beta, fs in self.finals.items():
            if beta in TARGETS:
                parts.append(float(np.mean([_near(f, TARGETS[beta]) for f in fs])))
            else:
                best = [max((_near(f, b) for f in fs), default=0.0) for b in TARGETS.values()]
                parts.append(float(np.mean(best)))
        return float(np.mean(parts)) if parts else 0.0

    def penalty(self) -> float:
        total = 0.0
        for beta in self.finals:
            share = self.landing_share.get(beta)
            slip = self.slip.get(beta)
            err = self.speed_error.get(beta)
            total += PENALTY * max(0.0, MIN_LANDING_SHARE - (share if share is not None else 0))
            total += PENALTY * max(0.0, (slip if slip is not None else 1.0) - MAX_SLIP)
            total += PENALTY * max(0.0, (err if err is not None else 1.0) - MAX_SPEED_ERROR)
        return total

    def score(self) -> float:
        """Lower is better: 0 is the paper's Fig. 5 with sane walking."""
        return 1.0 - self.closeness() + self.penalty()


def _near(f: float | None, branch: float) -> float:
    d = math.inf if f is None else abs(float(angle_diff(f, branch)))
    return math.exp(-((d / WIDTH) ** 2))


def _median(values: Sequence[float | None]) -> float | None:
    ok = [v for v in values if v is not None]
    return float(np.median(ok)) if ok else None


def evaluate_pull(
    params: ModelParams,
    *,
    n_init: int = 6,
    duration_s: float = 4.0,
    dt_s: float | None = None,
    nthread: int = 0,
    bistable: bool = False,
) -> PullEvaluation:
    """Closed-loop runs at beta 0.62 and 0.70 (and 0.655 if `bistable`) from n_init starts
    over the circle."""
    betas = [*TARGETS, *([BETA_BISTABLE] if bistable else [])]
    specs = spec_grid(betas, initial_values(n_init), duration_s=duration_s, dt_s=dt_s)
    results = simulate_batch(specs, params, nthread=nthread)
    finals: dict[float, list[float | None]] = {b: [] for b in betas}
    share: dict[float, list[float | None]] = {b: [] for b in betas}
    slip: dict[float, list[float | None]] = {b: [] for b in betas}
    err: dict[float, list[float | None]] = {b: [] for b in betas}
    for spec, res in zip(specs, results, strict=True):
        b = spec.beta
        if res.diverged or res.events.d31.size < 4:
            finals[b].append(None)
            continue
        finals[b].append(final_d31(res.events.d31))  # where it ends, settled or not
        share[b].append(res.measures.landing_swing_share)
        slip[b].append(res.measures.slip_fraction)
        v = nominal_speed(b, params.trajectory.stroke, params.trajectory.swing_duration) * 100
        err[b].append(
            None if res.measures.speed_cm_s is None else abs(res.measures.speed_cm_s - v) / v
        )
    return PullEvaluation(
        finals=finals,
        landing_share={b: _median(v) for b, v in share.items()},
        slip={b: _median(v) for b, v in slip.items()},
        speed_error={b: _median(v) for b, v in err.items()},
    )

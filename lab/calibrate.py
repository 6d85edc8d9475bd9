"""Calibrating the open parameters so that gait selection works as in the paper (Figs. 5, 7).

The paper states the outcome (tripod 2.9 rad at beta 0.62, metachronal 1.9 rad at 0.70, both
stable from 0.645 to 0.67), not the mechanics behind it. This module searches the parameters the
paper leaves open, each confined to a physically plausible range written down in
`SEARCH_SPACE`, scoring candidates on closed-loop runs (phase resetting on, many initial
Delta31) with the batch runner. optuna's TPE sampler does the search; its SQLite storage makes
a long study resumable and inspectable.

Nothing here touches the controller: a candidate changes the body, the legs' compliance, the
swing curve or the ground, and gait selection must follow from phase resetting alone.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from lab.objectives import (
    Evaluation,
    drift_score,
    evaluate,
    evaluate_pull,
    outcome_gap,
)
from lab.space import SEARCH_SPACE, WIDE_SPACE
from sim_core import ModelParams
from sim_core.contract import TWO_PI
from sim_core.research import BETA_BISTABLE, BETA_FAST, BETA_SLOW, phi_aep

OBJECTIVES = ("closed-loop", "drift", "pull")


def reachable(params: ModelParams, beta: float = BETA_FAST, samples: int = 64) -> bool:
    """Whether every leg can reach its whole swing curve and stance line (with 2% margin)."""
    from sim_core.research import inverse_kinematics, leg_geometry, swing_point

    geo = leg_geometry(params.replace(**{"femur_length": params.legs.femur_length * 0.98}))
    aep = phi_aep(beta)
    tip = np.empty(3)
    q = np.empty(3)
    for leg in range(6):
        for phi in np.linspace(0, TWO_PI, samples):
            swing_point(geo, leg, float(phi), aep, tip)
            if not inverse_kinematics(geo, leg, tip, q):
                return False
    return True


def calibrate(
    n_trials: int,
    *,
    storage: str | None = None,
    study_name: str = "gait-selection",
    seed: int = 0,
    base: ModelParams | None = None,
    duration_s: float = 6.0,
    n_init: int = 8,
    on_trial: Callable[[int, float, dict[str, float]], None] | None = None,
    betas: Sequence[float] = (BETA_FAST, BETA_BISTABLE, BETA_SLOW),
    seed_from: str | None = None,
    check_half_dt: bool = True,
    objective_name: str = "closed-loop",
    start_from: Sequence[dict[str, float]] = (),
) -> Any:
    """Run (or resume) an optuna study; returns the study. Needs `optuna` installed.

    seed_from: the name of an earlier study in the same storage whose evaluated trials are
    re-scored with the current `Evaluation.score` and added, so a changed score need not
    throw away the simulations already run.
    start_from: parameter sets (names of the search space) to evaluate before sampling.
    check_half_dt: also run every candidate at half the timestep and add the outcome
    differences to the score (each capped at pi). A first study without it found candidates
    whose gait selection was an artefact of the timestep (docs/REPRODUCTION.md).
    objective_name: "closed-loop" (settled Delta31 of many runs, `Evaluation.score`),
    "drift" (`drift_score`: the sign of the open-loop drift around the paper's branches, a
    smoother and ~5x cheaper signal; its winners still need the closed-loop check) or "pull"
    (`pull.PullEvaluation.score` over `pull.WIDE_SPACE`: how close short closed-loop runs at
    0.62 and 0.70 end to the branches, and at 0.655 whether each branch is reached if 0.655 is
    among `betas`, with walking-sanity penalties; the half-step check does not apply, its
    winners need `evaluate` at dt and dt/2).
    """
    if objective_name not in OBJECTIVES:
        raise ValueError(f"objective_name must be one of {OBJECTIVES}, not {objective_name!r}")
    import optuna

    space = WIDE_SPACE if objective_name == "pull" else SEARCH_SPACE

    base = base or ModelParams()
    sampler = optuna.samplers.TPESampler(seed=seed, multivariate=True)
    study = optuna.create_study(
        study_name=study_name, storage=storage, sampler=sampler, load_if_exists=True
    )
    if len(study.trials) == 0 and seed_from is None:
        study.enqueue_trial({k: base.leaf(k) for k in space})
    for point in start_from:  # earlier finds to evaluate first (the base fills what they omit)
        study.enqueue_trial({k: point.get(k, base.leaf(k)) for k in space})
    if len(study.trials) == 0 and seed_from is not None:
        if storage is None:
            raise ValueError("seed_from needs a persistent storage")
        _seed_study(study, seed_from, storage)

    def objective(trial: optuna.Trial) -> float:
        values = {
            name: trial.suggest_float(name, r.low, r.high, log=r.log) for name, r in space.items()
        }
        params = base.replace(**values)
        if not reachable(params):
            trial.set_user_attr("unreachable", True)
            return 100.0
        if objective_name == "pull":
            pe = evaluate_pull(params, n_init=n_init, duration_s=duration_s,
                               bistable=BETA_BISTABLE in betas)  # fmt: skip
            for b, fs in pe.finals.items():
                trial.set_user_attr(f"finals_{b}", [None if f is None else round(f, 3) for f in fs])
                trial.set_user_attr(f"landing_share_{b}", pe.landing_share[b])
                trial.set_user_attr(f"slip_{b}", pe.slip[b])
                trial.set_user_attr(f"speed_error_{b}", pe.speed_error[b])
            trial.set_user_attr("closeness", pe.closeness())
            s = pe.score()
            if on_trial is not None:
                on_trial(trial.number, s, values)
            return s
        if objective_name == "drift":
            parts = drift_score(params)
            for b, v in parts.items():
                trial.set_user_attr(f"drift_score_{b}", v)
            s = -sum(parts.values())
            if on_trial is not None:
                on_trial(trial.number, s, values)
            return s
        ev = evaluate(params, betas=betas, n_init=n_init, duration_s=duration_s)
        for b, fs in ev.finals.items():
            trial.set_user_attr(f"finals_{b}", [None if f is None else round(f, 3) for f in fs])
        trial.set_user_attr("speed_error", ev.speed_error)
        trial.set_user_attr("max_slip", ev.max_slip)
        s = ev.score()
        if check_half_dt:
            half = evaluate(params, betas=betas, n_init=n_init, duration_s=duration_s,
                            dt_s=params.numerics.dt / 2)  # fmt: skip
            gap = outcome_gap(ev, half)
            trial.set_user_attr("half_dt_gap", gap)
            s += gap
        if on_trial is not None:
            on_trial(trial.number, s, values)
        return s

    study.optimize(objective, n_trials=n_trials)
    return study


def _seed_study(study: Any, source: str, storage: str) -> None:
    import optuna

    old = optuna.load_study(study_name=source, storage=storage)
    dists: dict[str, optuna.distributions.BaseDistribution]
    dists = {n: optuna.distributions.FloatDistribution(r.low, r.high, log=r.log)
             for n, r in SEARCH_SPACE.items()}  # fmt: skip
    for t in old.trials:
        if t.value is None or not all(k in t.params for k in SEARCH_SPACE):
            continue
        attrs = t.user_attrs
        if attrs.get("unreachable"):
            value = t.value
        else:
            finals = {float(k.split("_", 1)[1]): v for k, v in attrs.items()
                      if k.startswith("finals_")}  # fmt: skip
            ev = Evaluation(
                params=dict(t.params), finals=finals, speed_error=attrs.get("speed_error", 0.0),
                max_slip=attrs.get("max_slip", 0.0), diverged=0,
            )  # fmt: skip
            value = ev.score()
        study.add_trial(optuna.trial.create_trial(
            params={k: t.params[k] for k in SEARCH_SPACE}, distributions=dists, value=value,
            user_attrs=dict(attrs),
        ))  # fmt: skip

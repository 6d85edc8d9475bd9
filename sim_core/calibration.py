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

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim_core.gait import angle_diff, circular_mean
from sim_core.params import ModelParams, nominal_speed
from sim_core.runner import simulate_batch
from sim_core.spec import RunSpec

TRIPOD_BRANCH = 2.9  # rad, paper Fig. 5, beta = 0.62
METACHRONAL_BRANCH = 1.9  # rad, paper Fig. 5, beta = 0.70
BETA_FAST = 0.62
BETA_SLOW = 0.70
BETA_BISTABLE = 0.655
# rad of score per unit of speed error or slip beyond 10%: walking properly (the sim_core
# acceptance) outranks a closer Delta31 (0.1 of excess slip costs as much as 3 rad of Delta31)
WALK_PENALTY = 30.0
OBJECTIVES = ("closed-loop", "drift", "pull")


@dataclass(frozen=True)
class Range:
    low: float
    high: float
    log: bool
    reason: str


SEARCH_SPACE: dict[str, Range] = {
    "kp_lift": Range(5e-4, 2e-2, True, "static sag ~0.02-0.7 mm under a tripod's load"),
    "kd_lift": Range(5e-6, 3e-4, True, "leg time constants kd/kp ~1 ms to ~0.3 s: muscle-like"),
    "kp_yaw": Range(5e-4, 2e-2, True, "fore-aft compliance of the same order as the lift joints"),
    "kd_yaw": Range(5e-6, 3e-4, True, "fore-aft time constants as for the lift joints"),
    "swing_height": Range(0.3e-3, 1.5e-3, False, "foot clearance 0.3-1.5 mm, below the femur"),
    "swing_shape": Range(0.5, 2.0, False, "swing descent from gentle to steep near the AEP"),
    "com_offset_x": Range(-4e-3, 4e-3, False, "centre of mass within the thorax, +-4 mm"),
    "stand_height": Range(5.5e-3, 8.5e-3, False, "keeps every tip target within the leg's reach"),
    "foot_y": Range(9e-3, 13e-3, False, "sprawl from 4 to 8 mm beyond the body's side"),
    "stance_x_fore": Range(9e-3, 15e-3, False, "fore tips ahead of the fore coxae"),
    "stance_x_hind": Range(-15e-3, -9e-3, False, "hind tips behind the hind coxae"),
    "contact_timeconst": Range(2e-4, 2e-3, True, "stiff to moderately soft ground/tarsus"),
}


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
            total += 2 * math.pi
        total += WALK_PENALTY * max(0.0, self.speed_error - 0.10)
        total += WALK_PENALTY * max(0.0, self.max_slip - 0.10)
        return total


def reachable(params: ModelParams, beta: float = BETA_FAST, samples: int = 64) -> bool:
    """Whether every leg can reach its whole swing curve and stance line (with 2% margin)."""
    from sim_core.legs import inverse_kinematics, pack_geometry, swing_point

    geo = pack_geometry(params.model_copy(update={"femur_length": params.femur_length * 0.98}))
    phi_aep = 2 * math.pi * (1 - beta)
    tip = np.empty(3)
    q = np.empty(3)
    for leg in range(6):
        for phi in np.linspace(0, 2 * math.pi, samples):
            swing_point(geo, leg, float(phi), phi_aep, tip)
            if not inverse_kinematics(geo, leg, tip, q):
                return False
    return True


def initial_values(n: int) -> np.ndarray:
    """n initial Delta31 spread evenly over the circle (offset off the symmetric points)."""
    return np.linspace(0.0, 2 * math.pi, n, endpoint=False) + math.pi / n


def evaluate(
    params: ModelParams,
    betas: Sequence[float] = (BETA_FAST, BETA_BISTABLE, BETA_SLOW),
    n_init: int = 8,
    duration_s: float = 6.0,
    dt_s: float | None = None,
    nthread: int = 0,
) -> Evaluation:
    inits = initial_values(n_init)
    specs = [
        RunSpec(beta=b, d31_init=float(x), duration_s=duration_s, dt_s=dt_s)
        for b in betas
        for x in inits
    ]
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
        finals[spec.beta].append(_settled(res.d31))
        v = nominal_speed(spec.beta, params.stroke, params.swing_duration) * 100
        if res.speed_cm_s is not None:
            speed_err = max(speed_err, abs(res.speed_cm_s - v) / v)
        if res.slip_fraction is not None:
            slip = max(slip, res.slip_fraction)
    return Evaluation(
        params={k: getattr(params, k) for k in SEARCH_SPACE},
        finals=finals,
        speed_error=speed_err,
        max_slip=slip,
        diverged=diverged,
    )


def _settled(d31: np.ndarray, last: int = 8, tol: float = 0.1) -> float | None:
    """Mean of the last samples if they have stopped drifting (total drift below tol)."""
    if d31.size < last:
        return None
    tail = d31[-last:]
    if abs(float(angle_diff(tail[-1], tail[0]))) > tol:
        return None
    return circular_mean(tail)


def calibrate(
    n_trials: int,
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

    from sim_core.pull import WIDE_SPACE, evaluate_pull

    space = WIDE_SPACE if objective_name == "pull" else SEARCH_SPACE

    base = base or ModelParams()
    sampler = optuna.samplers.TPESampler(seed=seed, multivariate=True)
    study = optuna.create_study(
        study_name=study_name, storage=storage, sampler=sampler, load_if_exists=True
    )
    if len(study.trials) == 0 and seed_from is None:
        study.enqueue_trial({k: getattr(base, k) for k in space})
    for point in start_from:  # earlier finds to evaluate first (the base fills what they omit)
        study.enqueue_trial({k: point.get(k, getattr(base, k)) for k in space})
    if len(study.trials) == 0 and seed_from is not None:
        if storage is None:
            raise ValueError("seed_from needs a persistent storage")
        _seed_study(study, seed_from, storage)

    def objective(trial: optuna.Trial) -> float:
        values = {
            name: trial.suggest_float(name, r.low, r.high, log=r.log) for name, r in space.items()
        }
        params = base.model_copy(update=values)
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
                            dt_s=params.dt / 2)  # fmt: skip
            gap = outcome_gap(ev, half)
            trial.set_user_attr("half_dt_gap", gap)
            s += gap
        if on_trial is not None:
            on_trial(trial.number, s, values)
        return s

    study.optimize(objective, n_trials=n_trials)
    return study


DRIFT_GRID = np.linspace(0.0, 2 * math.pi, 18, endpoint=False) + math.pi / 18
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
        d, _ = open_loop_drift(params, beta, DRIFT_GRID.tolist(), duration_s=duration_s)
        sign = np.sign(angle_diff(target, DRIFT_GRID))
        weight = (np.abs(angle_diff(target, DRIFT_GRID)) > 0.15).astype(float)
        push = np.where(np.isnan(d), -1.0, np.tanh(sign * d / DRIFT_SCALE))
        out[beta] = float(np.sum(weight * push) / weight.sum())
    return out


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


@dataclass
class ReturnMap:
    """Pairs (Delta31_n, Delta31_{n+lag}) at leg-1 touchdowns, the paper's Fig. 7 construction."""

    beta: float
    lag: int
    x: np.ndarray
    y: np.ndarray

    def drift_per_cycle(self, bins: int = 24) -> tuple[np.ndarray, np.ndarray]:
        """Mean (y - x) / lag in bins of x over the circle: > 0 pushes Delta31 up."""
        edges = np.linspace(0, 2 * math.pi, bins + 1)
        d = angle_diff(self.y, self.x) / self.lag
        idx = np.clip(np.digitize(self.x, edges) - 1, 0, bins - 1)
        centers = 0.5 * (edges[1:] + edges[:-1])
        means = np.array([d[idx == k].mean() if (idx == k).any() else np.nan for k in range(bins)])
        return centers, means


def return_map(
    params: ModelParams | None,
    beta: float,
    inits: Sequence[float],
    duration_s: float = 2.0,
    lag: int = 4,
    skip: int = 2,
    dt_s: float | None = None,
    nthread: int = 0,
) -> ReturnMap:
    """Delta31(n) -> Delta31(n + lag) from many initial values (first `skip` cycles dropped)."""
    specs = [RunSpec(beta=beta, d31_init=float(x) % (2 * math.pi), duration_s=duration_s, dt_s=dt_s)
             for x in inits]  # fmt: skip
    xs: list[float] = []
    ys: list[float] = []
    for res in simulate_batch(specs, params, nthread=nthread):
        d = res.d31[skip:]
        if res.diverged or d.size <= lag:
            continue
        xs.extend(d[:-lag].tolist())
        ys.extend(d[lag:].tolist())
    return ReturnMap(beta=beta, lag=lag, x=np.array(xs), y=np.array(ys))


@dataclass(frozen=True)
class Outcome:
    """Where the runs from many initial values ended at one beta: a branch census."""

    beta: float
    finals: list[float | None]

    def branch(self, name: str) -> tuple[int, float | None]:
        """(how many runs settled in the gait `name`, their circular-mean Delta31)."""
        from sim_core.gait import classify_gait

        hits = [f for f in self.finals if f is not None and classify_gait(f) == name]
        return len(hits), (circular_mean(hits) if hits else None)


def sensitivity(
    params: ModelParams,
    names: Sequence[str] | None = None,
    rel: float = 0.10,
    betas: Sequence[float] = (BETA_FAST, BETA_SLOW),
    n_init: int = 8,
    duration_s: float = 6.0,
    dt_s: float | None = None,
) -> dict[str, dict[str, list[Outcome]]]:
    """Outcomes for each parameter moved by -rel and +rel (and the base, under 'base').

    Every perturbed set runs in one batch call; a perturbation that leaves the model's own
    bounds is skipped (reported as missing).
    """
    names = list(names or SEARCH_SPACE)
    variants: list[tuple[str, str, ModelParams]] = [("base", "0", params)]
    for name in names:
        v = getattr(params, name)
        for sign, label in ((-1, "-"), (1, "+")):
            try:
                variants.append(
                    (name, label, params.model_copy(update={name: v * (1 + sign * rel)}))
                )
            except ValueError:
                continue
    out: dict[str, dict[str, list[Outcome]]] = {}
    for name, label, p in variants:
        ev = evaluate(p, betas=betas, n_init=n_init, duration_s=duration_s, dt_s=dt_s)
        out.setdefault(name, {})[label] = [Outcome(b, ev.finals[b]) for b in betas]
    return out


def open_loop_drift(
    params: ModelParams,
    beta: float,
    grid: Sequence[float],
    duration_s: float = 1.5,
    dt_s: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Delta31 drift per cycle the touchdowns would cause, with Delta31 held fixed.

    Resetting is off, so each run keeps its Delta31; the mean phase jump each leg's touchdown
    would cause, e_i = phi_AEP - phi_touchdown (after a third of the run), gives the drift
    1/4 [(e5 + e6) - (e1 + e2)] (middle legs lock to the mean of fore and hind). A cheap,
    deterministic look at the return map's shape, and at which lever moves it.
    Returns (drift (len(grid),), jumps (len(grid), 6)).
    """
    specs = [RunSpec(beta=beta, d31_init=float(x) % (2 * math.pi), duration_s=duration_s,
                     phase_reset=False, dt_s=dt_s) for x in grid]  # fmt: skip
    aep = 2 * math.pi * (1 - beta)
    jumps = np.full((len(specs), 6), np.nan)
    for k, res in enumerate(simulate_batch(specs, params)):
        if res.diverged:
            continue
        for leg in range(6):
            t, ph = res.touchdowns[leg], res.touchdown_phases[leg]
            sel = ph[t > duration_s / 3]
            if sel.size:
                jumps[k, leg] = float(np.mean(angle_diff(aep, sel)))
    drift = 0.25 * ((jumps[:, 4] + jumps[:, 5]) - (jumps[:, 0] + jumps[:, 1]))
    return drift, jumps

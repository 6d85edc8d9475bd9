"""Sixth campaign, point 3 (issue 52): search every invented parameter at once, both regimes in
the box, scored by free walks from both of the paper's branch values (`lab.walk_objective`).

    python -m lab.campaigns.campaign6_search --timeout-s 3600

The space holds campaign 5's (`SPACE5`) widened to the soft-leg regime (the named setting
`soft_legs` lies inside it), with the joints' time constants (kd / kp) as coordinates instead
of the dampings, the support ratio to 4, and the structure campaign 5 never varied: the swing's
shape, the scuff rule, the joints' armature and the body's thickness (its inertia). Resumable
as campaign 5's: the study in SQLite (`--storage`), every walk in the result cache (`--cache`),
the whole record exported after every trial (`--export`, committed; a fresh machine re-seeds
the study from it). Stops after `--trials` more trials or `--timeout-s`.

Not in the space (said so in docs/studies/campaign6.md): the penalty ground above 5e3 N/m
(stable only with RK4 at 2e-5 s, ~10x a walk's cost), the mass's distribution along each link
(no such parameter: a model change).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from lab.calibrate import reachable
from lab.campaigns.campaign5_search import add_trials, export, search_setup, suggest
from lab.space import Range
from lab.surface_search import (
    CONSTRAINT_SPACE,
    PENALTY_SPACE,
    SPACE5,
    coordinates,
    geometry,
)
from lab.walk_objective import (
    FAILED_SCORE,
    MISMATCH_WEIGHT,
    STARTS,
    Walk,
    against_paper,
    evaluate_walks,
    third_states,
)
from sim_core import ModelParams, ResultCache, get_backend
from sim_core.research import named_params

STUDY = "campaign6"

# campaign 5's box widened to hold the soft legs (kp_yaw 1.3e-3, kp_lift 7.7e-4, kd/kp 5 and
# 25 ms), each range with its reason; the dampings are searched as time constants
SPACE6: dict[str, Range] = {
    **{k: v for k, v in SPACE5.items() if k not in ("kd_yaw", "kd_lift")},
    "kp_yaw": Range(5e-4, 1.5e-2, True, "fore-aft stiffness: sag 0.003-0.1 rad (soft 1.3e-3)"),
    "kp_lift": Range(4e-4, 8e-3, True, "lift stiffness: sag 0.05-1 mm (soft 7.7e-4)"),
    "tau_yaw": Range(1e-3, 3e-2, True, "kd/kp of joint 1: 1-30 ms (default 6, soft 5)"),
    "tau_lift": Range(3e-4, 4e-2, True, "kd/kp of joints 2-3: 0.3-40 ms (default 1, soft 25)"),
    "support_ratio": Range(0.5, 4.0, True, "middle pair half to four times as stiff"),
    "velocity_feedforward_lift": Range(0.0, 1.2, False, "lift damping: velocity to error"),
    "swing_shape": Range(0.5, 3.0, False, "lift profile exponent: gentle to steep descent"),
    "scuff_fraction": Range(0.2, 0.8, False, "how early in swing a touch counts as landing"),
    "armature": Range(2e-11, 2e-9, True, "joint rotor inertia: a tenth to 10x the tibia's"),
    "body_thickness": Range(2e-3, 8e-3, False, "thorax 2-8 mm thick: the body's inertia"),
}


def _space(ground: str) -> dict[str, Range]:
    return SPACE6 | (CONSTRAINT_SPACE if ground == "constraint" else PENALTY_SPACE)


def params_of(values: dict[str, Any]) -> ModelParams:
    """`ModelParams` of a trial's values (geometry, and the dampings from time constants)."""
    v = dict(values)
    v["kd_yaw"] = v.pop("tau_yaw") * v["kp_yaw"]
    v["kd_lift"] = v.pop("tau_lift") * v["kp_lift"]
    return ModelParams.of(**geometry(v))


def point_of(p: ModelParams) -> dict[str, Any]:
    """The search's coordinates of `p` (for the starting points)."""
    c = coordinates(p)
    ground = str(p.leaf("ground"))
    out: dict[str, Any] = {"ground": ground, "trajectory_frame": p.trajectory.trajectory_frame}
    for n in _space(ground):
        if n == "tau_yaw":
            out[n] = p.joints.kd_yaw / p.joints.kp_yaw
        elif n == "tau_lift":
            out[n] = p.joints.kd_lift / p.joints.kp_lift
        else:
            out[n] = c[n] if n in c else p.leaf(n)
    return out


def _clip(point: dict[str, Any]) -> dict[str, Any]:
    """A starting point inside the box (a default that sits on an edge stays there)."""
    out = dict(point)
    for n, r in _space(point["ground"]).items():
        out[n] = min(r.high, max(r.low, float(out[n])))
    return out


def starting_points() -> list[dict[str, Any]]:
    """The defaults, the soft legs, the soft legs with stiffer middle legs (the notes' 3.5)."""
    soft = named_params("soft_legs")
    return [_clip(point_of(p)) for p in (ModelParams(), soft,
                                         named_params("soft_legs", support_ratio=3.5))]  # fmt: skip


def rescore(row: dict[str, Any]) -> dict[str, Any]:
    """An exported trial scored by today's reading of its stored walks (the walks' finals and
    drifts are the measurement; the score is a reading of them). Session 27 added the third
    states: a walk that leaves where the paper has only the other gait must end on that gait.
    Trials scored before it gain that part; a trial that has it is returned unchanged."""
    u = row.get("user_attrs", {})
    if "walks" not in u or "part_third_states" in u or row.get("value") is None:
        return row
    side = {k[0]: k for k in STARTS}
    walks = [Walk(side[s], b, f, d, h, f is None, None, None, None) for s, b, f, d, h in u["walks"]]
    part = MISMATCH_WEIGHT * third_states(walks)
    attrs = u | {"part_third_states": part, "against_paper": sum(map(against_paper, walks))}
    return row | {"value": row["value"] + part, "user_attrs": attrs}


def reseed(study: Any, path: Path) -> int:
    """Add the exported trials, re-scored (`rescore`), to an empty study (a fresh machine, or
    a study whose reading changed)."""
    rows = [rescore(r) for r in json.loads(path.read_text())["trials"]]
    return add_trials(study, rows, _space)


def objective_of(
    backend: Any, cache: ResultCache, values_of: Callable[[Any], dict[str, Any]]
) -> Callable[[Any], float]:
    """The search's objective: a trial's values (`values_of(trial)`) walked from both of the
    paper's branch values (`evaluate_walks`), the reading kept in the trial's attributes."""

    def objective(trial: Any) -> float:
        t0 = time.perf_counter()
        values = values_of(trial)
        try:
            params = params_of(values)
        except ValueError as exc:
            trial.set_user_attr("error", str(exc)[:300])
            return FAILED_SCORE
        if not reachable(params):
            trial.set_user_attr("error", "a tip target out of reach")
            return FAILED_SCORE
        score = evaluate_walks(params, cache, backend)
        for k, v in score.attrs().items():
            trial.set_user_attr(k, v)
        trial.set_user_attr("wall_s", round(time.perf_counter() - t0, 1))
        return score.score

    return objective


def reporter(exported: Path) -> Callable[[Any, Any], None]:
    """A callback that exports the study after every trial and prints one line per trial."""

    def report(study: Any, trial: Any) -> None:
        export(study, exported)
        u = trial.user_attrs
        best = study.best_trial
        print(
            f"#{trial.number} {trial.params.get('ground', '?')[:4]} score {trial.value:.4f} "
            f"folds M {u.get('metachronal_fold', float('nan')):.3f} "
            f"T {u.get('tripod_fold', float('nan')):.3f} against {u.get('against_paper')} "
            f"{u.get('wall_s')} s | best #{best.number} {best.value:.4f}",
            flush=True,
        )

    return report


def main() -> None:
    study, a = search_setup(__doc__ or "", STUDY, 600, 60, 6, reseed, starting_points)
    exported = Path(a.export)
    backend, cache = get_backend("local", a.workers), ResultCache(a.cache)
    objective = objective_of(backend, cache, lambda t: suggest(t, _space))
    study.optimize(
        objective, n_trials=a.trials, timeout=a.timeout_s, callbacks=[reporter(exported)]
    )


if __name__ == "__main__":
    main()

"""Fifth campaign, point 2 (issue 40): search every invented parameter at once on coarse drift
surfaces (`lab.surface_search`), with optuna's TPE over both grounds.

    python -m lab.campaigns.campaign5_search --timeout-s 3600

Resumable: the study lives in SQLite (`--storage`), every probe in the result cache
(`--cache`), and after every trial the whole record is exported to `--export` (committed, so
that a fresh machine re-seeds the study from it: `--export` is read back when the storage
holds no trial). Stops after `--trials` more trials or `--timeout-s`, whichever comes first;
a trial under way when the time is up finishes first.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from lab.calibrate import reachable
from lab.space import Range
from lab.surface_search import (
    CONSTRAINT_SPACE,
    FAILED_SCORE,
    FRAMES,
    GROUNDS,
    OBJECTIVE_BETAS,
    PAPER_METACHRONAL_FOLD,
    PAPER_TRIPOD_FOLD,
    PENALTY_SPACE,
    SPACE5,
    coordinates,
    evaluate_candidate,
    fold_of,
    geometry,
)
from sim_core import ModelParams, ResultCache, get_backend
from sim_core.contract import PARAMETER_NAMES

STUDY = "campaign5"


def _leaf_or_none(p: ModelParams, name: str) -> Any:
    return p.leaf(name) if name in PARAMETER_NAMES else None


def _space(ground: str) -> dict[str, Range]:
    return SPACE5 | (CONSTRAINT_SPACE if ground == "constraint" else PENALTY_SPACE)


def distributions(ground: str, space: Callable[[str], dict[str, Range]] = _space) -> dict[str, Any]:
    """optuna's distributions of a trial on `ground` (`space`: the ranges on each ground)."""
    import optuna

    d: dict[str, Any] = {
        "ground": optuna.distributions.CategoricalDistribution(GROUNDS),
        "trajectory_frame": optuna.distributions.CategoricalDistribution(FRAMES),
    }
    for n, r in space(ground).items():
        d[n] = optuna.distributions.FloatDistribution(r.low, r.high, log=r.log)
    return d


def suggest(
    trial: Any,
    space: Callable[[str], dict[str, Range]] = _space,
    grounds: Sequence[str] = GROUNDS,
    frames: Sequence[str] = FRAMES,
) -> dict[str, Any]:
    """A trial's values: the ground and the trajectories' frame (one of `grounds`, `frames`: a
    single choice holds it) and `space(ground)`'s ranges."""
    ground = trial.suggest_categorical("ground", tuple(grounds))
    values: dict[str, Any] = {
        "ground": ground,
        "trajectory_frame": trial.suggest_categorical("trajectory_frame", tuple(frames)),
    }
    for n, r in space(ground).items():
        values[n] = trial.suggest_float(n, r.low, r.high, log=r.log)
    return values


def starting_points() -> list[dict[str, Any]]:
    """The defaults on both grounds, and the +-10% study's lead (kp_lift x 0.9 removed the
    1.76 metachronal state at 0.62 and kept the tripod)."""
    base = ModelParams()
    out = []
    for ground in GROUNDS:
        p = base.replace(**{"ground": ground})
        c = coordinates(p)
        out.append({"ground": ground, "trajectory_frame": p.trajectory.trajectory_frame}
                   | {n: c.get(n, _leaf_or_none(p, n)) for n in _space(ground)})  # fmt: skip
    out.append(out[0] | {"kp_lift": 0.9 * base.joints.kp_lift})
    out.append(out[0] | {"kd_lift": 1.1 * base.joints.kd_lift})
    return out


def export(study: Any, path: Path) -> None:
    """Every finished trial as JSON, written atomically."""
    rows = [
        {
            "number": t.number,
            "state": t.state.name,
            "params": t.params,
            "value": t.value,
            "user_attrs": t.user_attrs,
            "datetime_complete": None
            if t.datetime_complete is None
            else t.datetime_complete.isoformat(),
        }
        for t in study.trials
        if t.state.is_finished()
    ]
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        json.dump({"study": study.study_name, "trials": rows}, f, indent=0)
    os.replace(tmp, path)


def rescore(row: dict[str, Any]) -> dict[str, Any]:
    """An exported trial with its folds re-read from its stored margins by today's `fold_of`
    (the margins are the measurement; the folds and the score are readings of them)."""
    u = row["user_attrs"]
    if "metachronal_margin" not in u:
        return row
    f_m = fold_of(OBJECTIVE_BETAS, u["metachronal_margin"], rising=True)
    f_t = fold_of(OBJECTIVE_BETAS, u["tripod_margin"], rising=False)
    parts = {k.removeprefix("part_"): v for k, v in u.items() if k.startswith("part_")}
    parts |= {"metachronal_fold": abs(f_m - PAPER_METACHRONAL_FOLD),
              "tripod_fold": abs(f_t - PAPER_TRIPOD_FOLD)}  # fmt: skip
    attrs = u | {"metachronal_fold": f_m, "tripod_fold": f_t}
    attrs |= {f"part_{k}": v for k, v in parts.items()}
    return row | {"value": float(sum(parts.values())), "user_attrs": attrs}


def reseed(study: Any, path: Path) -> int:
    """Add the exported trials, re-read by `rescore`, to an empty study (a fresh machine, or
    after a reading of the margins changed)."""
    rows = [rescore(r) for r in json.loads(path.read_text())["trials"]]
    return add_trials(study, rows)


def add_trials(
    study: Any, rows: list[dict[str, Any]], space: Callable[[str], dict[str, Range]] = _space
) -> int:
    """The completed exported `rows` added to `study` (their distributions from `space`)."""
    import optuna

    n = 0
    for r in rows:
        if r["state"] != "COMPLETE":
            continue
        study.add_trial(optuna.trial.create_trial(
            params=r["params"], distributions=distributions(r["params"]["ground"], space),
            value=r["value"], user_attrs=r["user_attrs"],
        ))  # fmt: skip
        n += 1
    return n


def search_setup(
    doc: str,
    name: str,
    trials: int,
    n_startup: int,
    seed: int,
    reseed: Callable[[Any, Path], int],
    starting_points: Callable[[], list[dict[str, Any]]],
) -> tuple[Any, argparse.Namespace]:
    """A campaign search's command line (`--trials`, `--timeout-s`, `--storage`, `--cache`,
    `--export`, `--workers`, `--seed`; defaults under out/<name> and docs/data) and its study
    `name`: TPE, opened from SQLite (resumed), else re-seeded from the export (`reseed`), else
    started with `starting_points`."""
    import optuna

    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--trials", type=int, default=trials)
    ap.add_argument("--timeout-s", type=float, default=None)
    ap.add_argument("--storage", default=f"sqlite:///out/{name}/search.db")
    ap.add_argument("--cache", default=f"out/{name}/cache")
    ap.add_argument("--export", default=f"docs/data/{name}_trials.json")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=seed)
    a = ap.parse_args()
    Path(f"out/{name}").mkdir(parents=True, exist_ok=True)
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    sampler = optuna.samplers.TPESampler(seed=a.seed, multivariate=True, group=True,
                                         n_startup_trials=n_startup)  # fmt: skip
    study = optuna.create_study(study_name=name, storage=a.storage,
                                sampler=sampler, load_if_exists=True)  # fmt: skip
    exported = Path(a.export)
    if not study.trials:
        if exported.exists():
            print(f"re-seeded {reseed(study, exported)} trials from {exported}")
        else:
            for point in starting_points():
                study.enqueue_trial(point)
    return study, a


def main() -> None:
    study, a = search_setup(__doc__ or "", STUDY, 400, 40, 5, reseed, starting_points)
    exported = Path(a.export)
    backend, cache = get_backend("local", a.workers), ResultCache(a.cache)

    def objective(trial: Any) -> float:
        t0 = time.perf_counter()
        values = suggest(trial)
        try:
            params = ModelParams.of(**geometry(values))
        except ValueError as exc:
            trial.set_user_attr("error", str(exc)[:300])
            return FAILED_SCORE
        if not reachable(params):
            trial.set_user_attr("error", "a tip target out of reach")
            return FAILED_SCORE
        score, surface = evaluate_candidate(params, cache, backend)
        for k, v in score.attrs().items():
            trial.set_user_attr(k, v)
        trial.set_user_attr("zeros", [[z.beta, round(z.d31, 3), z.stable] for z in surface.zeros])
        trial.set_user_attr("wall_s", round(time.perf_counter() - t0, 1))
        trial.set_user_attr("sim_s", surface.sim_s)
        return score.score

    def report(study: Any, trial: Any) -> None:
        export(study, exported)
        u = trial.user_attrs
        best = study.best_trial
        print(
            f"#{trial.number} {trial.params.get('ground', '?')[:4]} score {trial.value:.4f} "
            f"folds M {u.get('metachronal_fold', float('nan')):.3f} "
            f"T {u.get('tripod_fold', float('nan')):.3f} extra {u.get('extra_zeros')} "
            f"{u.get('wall_s')} s | best #{best.number} {best.value:.4f}",
            flush=True,
        )

    study.optimize(objective, n_trials=a.trials, timeout=a.timeout_s, callbacks=[report])


if __name__ == "__main__":
    main()

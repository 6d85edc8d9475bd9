"""Sixth campaign, point 3's local refinement (issue 52): CMA-ES around the search's best
settings, with the search's objective (free walks from both branch values).

    python -m lab.campaigns.campaign6_refine --seeds 333 364 0 --rounds 4 --timeout-s 2700

One CMA-ES study per seed (`optuna`'s `CmaEsSampler`, started at the seed's coordinates with
`--sigma0` in the unit box each coordinate's range maps to, log ranges in log), the seed's
ground and trajectory frame held. The seed itself is each study's first trial (its walks come
from the result cache, so it costs nothing). The studies advance in turn, one generation
(`--popsize` trials) each per round, so a timeout leaves every seed refined alike. Resumable:
the studies in SQLite, every walk in the campaign's cache, the trials exported after each one
(`--export-dir`/campaign6_refine_<seed>.json, committed).
"""

from __future__ import annotations

import argparse
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

from lab.calibrate import reachable
from lab.campaigns.campaign5_search import suggest
from lab.campaigns.campaign6_confirm import trial_values
from lab.campaigns.campaign6_search import (
    _space,
    objective_of,
    params_of,
    reporter,
)
from sim_core import ResultCache, get_backend

SIGMA0 = 0.03  # 3% of each range: at 0.1 (a tenth) 10 of 12 samples lost the seeds' metachronal end
POPSIZE = 8  # trials per CMA-ES generation (its default for 30 coordinates is 14): 4 rounds fit


def held(seed: dict[str, Any]) -> Callable[[Any], dict[str, Any]]:
    """A trial's values with the seed's ground and frame held, every range of `_space` searched."""
    grounds, frames = (seed["ground"],), (seed["trajectory_frame"],)
    return lambda trial: suggest(trial, _space, grounds, frames)


def main() -> None:
    import optuna

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[333, 364, 0])
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--popsize", type=int, default=POPSIZE)
    ap.add_argument("--sigma0", type=float, default=SIGMA0)
    ap.add_argument("--timeout-s", type=float, default=None)
    ap.add_argument("--storage", default="sqlite:///out/campaign6/refine.db")
    ap.add_argument("--cache", default="out/campaign6/cache")
    ap.add_argument("--export-dir", default="docs/data")
    ap.add_argument("--workers", type=int, default=2)
    a = ap.parse_args()
    Path("out/campaign6").mkdir(parents=True, exist_ok=True)
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    warnings.filterwarnings("ignore", category=FutureWarning)  # optuna 4.9: x0 deprecated
    backend, cache = get_backend("local", a.workers), ResultCache(a.cache)
    studies = []
    for n in a.seeds:
        seed = trial_values(n)
        if not reachable(params_of(seed)):
            raise SystemExit(f"seed #{n} is not walkable")
        floats = {k: float(v) for k, v in seed.items() if k in _space(seed["ground"])}
        sampler = optuna.samplers.CmaEsSampler(
            x0=floats, sigma0=a.sigma0, popsize=a.popsize, seed=n,
            warn_independent_sampling=False,
        )  # fmt: skip
        study = optuna.create_study(study_name=f"campaign6_refine_{n}", storage=a.storage,
                                    sampler=sampler, load_if_exists=True)  # fmt: skip
        if not study.trials:
            study.enqueue_trial(seed)
        exported = Path(a.export_dir) / f"campaign6_refine_{n}.json"
        studies.append((n, study, objective_of(backend, cache, held(seed)), exported))
    t0 = time.monotonic()
    for r in range(a.rounds):
        for n, study, objective, exported in studies:
            left = None if a.timeout_s is None else a.timeout_s - (time.monotonic() - t0)
            if left is not None and left <= 0:
                return
            print(f"round {r + 1}, seed #{n}", flush=True)
            study.optimize(objective, n_trials=a.popsize, timeout=left,
                           callbacks=[reporter(exported)])  # fmt: skip


if __name__ == "__main__":
    main()

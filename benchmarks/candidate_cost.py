"""A gait campaign's candidate (its coarse drift surface and score, `lab.surface_search`) on
the campaign-5 probes (0.5 s settle + 1 s average) and on the issue-54 probes (0.25 s + 0.5 s),
side by side in one run, each from an empty cache, for a few parameter sets: wall time on
`--workers` local workers, the ratio, and what each reads (folds, margins, branch values,
score), to see whether the cheaper candidate reads the same landscape (the soft legs: it does
not; docs/NUMERICS.md).

    PYTHONPATH=. .venv/bin/python benchmarks/candidate_cost.py [--workers 2] [--json out.json]

(PYTHONPATH: the lab is not installed; it runs from a checkout.)

Run it alone: a loaded machine measures the load.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path
from typing import Any

from lab.surface_search import FAST_OBJECTIVE_CONFIG, OBJECTIVE_CONFIG, evaluate_candidate
from sim_core import ModelParams, ResultCache, get_backend
from sim_core.contract import SurfaceConfig
from sim_core.research import named_params

SETS = {"defaults": ModelParams(), "soft_legs": named_params("soft_legs")}
READ = ("metachronal_fold", "tripod_fold", "metachronal_value", "tripod_value", "extra_zeros")


def candidate(
    params: ModelParams, config: SurfaceConfig, workers: int, cache: Path
) -> dict[str, Any]:
    """One candidate's wall time and reading."""
    backend = get_backend("local", workers)
    t0 = time.perf_counter()
    try:
        score, _ = evaluate_candidate(params, ResultCache(cache), backend, config=config)
    finally:
        backend.close()
    wall = time.perf_counter() - t0
    reading = {k: getattr(score, k) for k in READ}
    return {"wall_s": round(wall, 2), "score": round(score.score, 4), **reading,
            "metachronal_margin": score.metachronal_margin,
            "tripod_margin": score.tripod_margin}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--json", type=Path, help="also write the measurement here")
    args = ap.parse_args()
    out: dict[str, Any] = {}
    with tempfile.TemporaryDirectory(prefix="candidate-cost-") as tmp:
        for name, params in SETS.items():
            for label, cfg in (("campaign5", OBJECTIVE_CONFIG), ("fast", FAST_OBJECTIVE_CONFIG)):
                out[f"{name}/{label}"] = r = candidate(params, cfg, args.workers,
                                                      Path(tmp) / f"{name}-{label}")  # fmt: skip
                folds = f"folds M {r['metachronal_fold']:.3f} T {r['tripod_fold']:.3f}"
                vals = f"values M {r['metachronal_value']} T {r['tripod_value']}"
                print(f"{name:>9} {label:>9}: {r['wall_s']:6.1f} s  score {r['score']:.4f}  "
                      f"{folds}  {vals}  extra {r['extra_zeros']}", flush=True)  # fmt: skip
            a, b = out[f"{name}/campaign5"], out[f"{name}/fast"]
            print(f"{name:>9} ratio fast/campaign5: {b['wall_s'] / a['wall_s']:.2f}\n")
    if args.json:
        args.json.write_text(json.dumps({"workers": args.workers, "runs": out}, indent=1))


if __name__ == "__main__":
    main()

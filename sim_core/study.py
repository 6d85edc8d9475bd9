"""`insect-gait study`: the gait-selection evidence for the current defaults, as files.

Runs Fig. 5 (Delta31 from many initial values at beta 0.62 and 0.70), the return maps at
0.62 / 0.655 / 0.70 (Fig. 7 construction) and, unless skipped, the +-10% sensitivity study, and
writes PNG figures and the JSON behind them. It measures; it decides nothing.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from sim_core.calibration import (
    BETA_BISTABLE,
    BETA_FAST,
    BETA_SLOW,
    Outcome,
    initial_values,
    return_map,
    sensitivity,
)
from sim_core.experiments import map_fixed_points
from sim_core.params import ModelParams
from sim_core.runner import simulate_batch
from sim_core.spec import RunSpec


def run_study(
    out: Path,
    params: ModelParams | None = None,
    n_init: int = 12,
    duration_s: float = 10.0,
    map_inits: int = 24,
    map_duration_s: float = 3.0,
    with_sensitivity: bool = True,
    log: Callable[[str], None] = print,
) -> dict[str, Any]:
    from sim_core.plots import plot_fig5, plot_return_maps, plot_sensitivity

    p = params or ModelParams()
    out.mkdir(parents=True, exist_ok=True)
    report: dict[str, Any] = {"params": p.model_dump()}
    t0 = time.perf_counter()

    inits = initial_values(n_init)
    specs = [RunSpec(beta=b, d31_init=float(x), duration_s=duration_s)
             for b in (BETA_FAST, BETA_SLOW) for x in inits]  # fmt: skip
    runs = simulate_batch(specs, p)
    by_beta = {BETA_FAST: runs[:n_init], BETA_SLOW: runs[n_init:]}
    plot_fig5(by_beta, out / "fig5_d31_convergence.png")
    report["fig5"] = {
        str(b): [
            {"d31_init": float(x), **r.summary(), "d31": None}
            for x, r in zip(inits, rs, strict=True)
        ]
        for b, rs in by_beta.items()
    }
    log(f"[{time.perf_counter() - t0:5.0f} s] Fig. 5 runs done")

    maps = [
        return_map(p, b, initial_values(map_inits).tolist(), duration_s=map_duration_s)
        for b in (BETA_FAST, BETA_BISTABLE, BETA_SLOW)
    ]
    plot_return_maps(maps, out / "fig7_return_maps.png")
    report["return_maps"] = {
        str(rm.beta): {
            "x": rm.x.tolist(),
            "y": rm.y.tolist(),
            "fixed_points": [fp.__dict__ for fp in map_fixed_points(rm)],
        }
        for rm in maps
    }
    log(f"[{time.perf_counter() - t0:5.0f} s] return maps done")

    if with_sensitivity:
        sens = sensitivity(p, n_init=8, duration_s=6.0)
        plot_sensitivity(sens, out / "sensitivity_tornado.png")
        report["sensitivity"] = {
            name: {label: [_census(o) for o in outs] for label, outs in d.items()}
            for name, d in sens.items()
        }
        log(f"[{time.perf_counter() - t0:5.0f} s] sensitivity done")
    report["wall_s"] = time.perf_counter() - t0
    (out / "study.json").write_text(json.dumps(report, indent=1, default=float))
    write_bifurcation(report, out / "bifurcation.json")
    return report


def write_bifurcation(report: dict[str, Any], path: Path) -> None:
    """The return maps' fixed points as (beta, Delta31) points, series 'stable'/'unstable': the
    file the viewer's bifurcation panel draws (web/bifurcation.py reads this shape)."""
    points = [
        {"beta": float(beta), "d31": fp["d31"], "branch": "stable" if fp["stable"] else "unstable"}
        for beta, rm in report["return_maps"].items()
        for fp in rm["fixed_points"]
    ]
    path.write_text(json.dumps({"source": "insect-gait study: return-map fixed points",
                                "points": points}, indent=1))  # fmt: skip


def _census(o: Outcome) -> dict[str, Any]:
    tri = o.branch("tripod")
    meta = o.branch("metachronal")
    return {
        "beta": o.beta,
        "finals": o.finals,
        "tripod": {"n": tri[0], "d31": tri[1]},
        "metachronal": {"n": meta[0], "d31": meta[1]},
    }

"""Fifth campaign, point 4's first checks (issue 40): is a search candidate's loop real?

    python -m lab.campaigns.campaign5_confirm --trial N
    python -m lab.campaigns.campaign5_confirm --params '{"kp_lift": 0.0027}'

For one candidate (a trial of `docs/data/campaign5_trials.json`, or ModelParams overrides):
1. its refined drift surface over beta 0.60-0.72 by 0.01 (Fig. 8's protocol): where the
   metachronal and tripod branches end, read from stable zeros (not from the coarse margins);
2. settled free runs (40 s, the project's settled rule) from the tripod (3.0) and the
   metachronal (1.9) side at the betas beside each refined fold, at dt and at dt/2: the states
   they end in, the landing share, the speed against eq. 2.
Prints a table and writes `confirm_<name>.json` under --out. The search scores coarse margins;
only this (and then the finder and +-10% of each calibrated parameter) can make a claim.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

from lab.surface_search import METACHRONAL_WINDOW, TRIPOD_WINDOW, geometry
from sim_core import (
    ModelParams,
    ResultCache,
    RunSpec,
    drift_surface,
    get_backend,
    nominal_speed,
    simulate_batch,
)
from sim_core.contract import DriftSurface, SurfaceConfig, surface_grid

BETAS = surface_grid(0.60, 0.72, 0.01)
STARTS = {"tripod side": 3.0, "metachronal side": 1.9}
FREE_RUN_S = 40.0


def candidate(args: argparse.Namespace) -> tuple[str, ModelParams]:
    if args.trial is not None:
        rows = json.loads(Path(args.trials).read_text())["trials"]
        row = next(r for r in rows if r["number"] == args.trial)
        return f"trial{args.trial}", ModelParams.of(**geometry(row["params"]))
    return "params", ModelParams.of(**json.loads(args.params))


def branch_betas(surface: DriftSurface, window: tuple[float, float]) -> list[float]:
    def has(b: float) -> bool:
        return any(z.stable and window[0] <= z.d31 <= window[1] for z in surface.zeros_at(b))

    return [b for b in surface.betas if has(b)]


def fold_end(betas: list[float], grid_betas: list[float], high: bool) -> float | None:
    """Where a branch ends: the tripod's (`high`) is the last beta of its stretch from the
    lowest beta it lives at, the metachronal's the first of its stretch down from the highest
    (an isolated zero beyond a gap is not the branch's end)."""
    if not betas:
        return None
    order = sorted(grid_betas) if high else sorted(grid_betas, reverse=True)
    inside = set(betas)
    start = order.index(min(betas) if high else max(betas))
    end = order[start]
    for b in order[start:]:
        if b not in inside:
            break
        end = b
    return end


def ramps(params: ModelParams) -> list[dict[str, Any]]:
    """Fig. 6a's two protocols at the reproduction's rate: from the metachronal side at 0.70
    down to 0.62 and back, and from the tripod at 0.62 up to 0.70 and back."""
    from sim_core import sweep
    from sim_core.research import ReproduceConfig

    cfg = ReproduceConfig()
    out = []
    for start, turn, d31 in ((cfg.beta_high, cfg.beta_low, cfg.start_d31),
                             (cfg.beta_low, cfg.beta_high, cfg.tripod_start_d31)):  # fmt: skip
        res = sweep(RunSpec(beta=start, d31_init=d31), parameter="beta", turn=turn,
                    hold_s=cfg.hold_s, ramp_s=cfg.ramp_s, params=params)  # fmt: skip
        s = res.summary
        first = [round(x["value"], 4) for x in s["first_leg"]]
        second = [round(x["value"], 4) for x in s["second_leg"]]
        out.append({"start": start, "turn": turn, "first_leg_switches": first,
                    "second_leg_switches": second, "loop": s["loop"], "width": s["width"],
                    "gaits": [s["gait_at_start"], s["gait_at_turn"], s["gait_at_end"]],
                    "error": res.error})  # fmt: skip
    return out


def free_runs(params: ModelParams, betas: list[float]) -> list[dict[str, Any]]:
    half = params.numerics.dt / 2
    specs = [RunSpec(beta=b, d31_init=d, duration_s=FREE_RUN_S, dt_s=dt)
             for b in betas for d in STARTS.values() for dt in (None, half)]  # fmt: skip
    out = []
    for spec, res in zip(specs, simulate_batch(specs, params, progress=True), strict=True):
        s = res.summary()
        v0 = 100 * nominal_speed(
            spec.beta, params.trajectory.stroke, params.trajectory.swing_duration
        )
        out.append({
            "beta": spec.beta, "start": spec.d31_init, "half_dt": spec.dt_s is not None,
            "final": s["d31_final"], "settled": s["settled"], "gait": s["gait"],
            "landing_share": s["landing_swing_share"],
            "speed_ratio": None if s["speed_cm_s"] is None else s["speed_cm_s"] / v0,
            "error": s["error"],
        })  # fmt: skip
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trial", type=int, default=None)
    ap.add_argument("--trials", default="docs/data/campaign5_trials.json")
    ap.add_argument("--params", default="{}")
    ap.add_argument("--cache", default="out/campaign5/cache")
    ap.add_argument("--out", default="out/campaign5")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--free-betas", default="",
                    help="more betas for the free runs, comma-separated")  # fmt: skip
    ap.add_argument("--ramps", action="store_true", help="also Fig. 6a's two beta ramps")
    a = ap.parse_args()
    name, params = candidate(a)
    t0 = time.perf_counter()
    backend = get_backend("local", a.workers)
    surface = drift_surface(BETAS, cache=ResultCache(a.cache), backend=backend,
                            config=SurfaceConfig(), params=params, progress=True)  # fmt: skip
    meta, trip = branch_betas(surface, METACHRONAL_WINDOW), branch_betas(surface, TRIPOD_WINDOW)
    print(f"{name}: refined surface ({surface.sim_s:.0f} simulated s, "
          f"{time.perf_counter() - t0:.0f} s): metachronal stable at {meta}; "
          f"tripod at {trip}")  # fmt: skip
    around: set[float] = {float(x) for x in a.free_betas.split(",") if x.strip()}
    for betas, high in ((meta, False), (trip, True)):
        b = fold_end(betas, list(surface.betas), high)
        if b is not None:
            around |= {round(b - 0.01, 2), b, round(b + 0.01, 2)}
    runs = free_runs(params, sorted(x for x in around if 0.5 < x < 1.0))
    for r in runs:
        final = "failed" if r["final"] is None else f"{r['final']:.3f}"
        print(f"  beta {r['beta']:.2f} from {r['start']} {'dt/2' if r['half_dt'] else 'dt  '}: "
              f"{final} {r['gait']} settled={r['settled']} landing {r['landing_share']} "
              f"speed x{r['speed_ratio'] and round(r['speed_ratio'], 3)}")  # fmt: skip
    swept = ramps(params) if a.ramps else []
    for r in swept:
        print(f"  ramp beta {r['start']} -> {r['turn']} -> {r['start']}: switches on the way "
              f"{r['first_leg_switches']}, back {r['second_leg_switches']}, loop {r['loop']}, "
              f"gaits (start, turn, end) {r['gaits']}")  # fmt: skip
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    report = {"name": name, "params": params.model_dump(mode="json", exclude_defaults=True),
              "metachronal_betas": meta, "tripod_betas": trip,
              "zeros": [z.model_dump() for z in surface.zeros], "free_runs": runs,
              "ramps": swept, "wall_s": time.perf_counter() - t0}  # fmt: skip
    (out / f"confirm_{name}.json").write_text(json.dumps(report))
    print(f"{report['wall_s']:.0f} s; wrote {out / f'confirm_{name}.json'}")


if __name__ == "__main__":
    main()

"""The atlases' walk-only states at half the step (the checks a walk's hit needs).

Usage: python -m lab.campaigns.atlas_walk_states_dt2 [--workers 2]

Every stable state of the four committed atlases (mass and slope, both grounds) that only a walk
found (provenance "walk") is walked again from the same start at dt/2 (the walk's try and
length), and read by the same settled rule. Prints, per state, the default-step final, its
landing share (`landing_swing_share`: 1 = feet land at the AEP), and the dt/2 final; a state
holds at dt/2 when that walk settles within 0.05 rad of it. Writes
docs/data/atlas_walk_states_dt2.json. Run alone on the machine (a study owns the CPU).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from sim_core import (
    ModelParams,
    ResultCache,
    WalkConfig,
    default_cache_dir,
    get_backend,
    run_task,
    run_tasks,
)
from sim_core.contract import RunTemplate, SurfaceAtlas, settling

ROOT = Path(__file__).resolve().parents[2]  # the checkout
FIGURES = ROOT / "docs" / "figures"
SAME_RAD = 0.05  # the dt/2 check's tolerance (docs: the four checks)
# finals this close are one state: the walks' merge distance (the finder's CLUSTER_TOL)
ONE_STATE_RAD = WalkConfig().merge_rad


def walk_only_states() -> list[dict[str, Any]]:
    """(atlas, ground, beta, value, state, the start of the walk that settled on it)."""
    out = []
    for axis in ("mass", "slope"):
        for ground in ("constraint", "penalty"):
            atlas = SurfaceAtlas.model_validate_json(
                (FIGURES / f"surface_atlas_{axis}_{ground}.json").read_text()
            )
            for pt in atlas.points:
                for x, source in zip(pt.stable, pt.provenance, strict=True):
                    if source != "walk":
                        continue
                    start = next(w.start for w in pt.walks if w.settled and w.final is not None
                                 and abs(w.final - x) <= ONE_STATE_RAD)  # fmt: skip
                    out.append({"axis": axis, "param": atlas.param, "ground": ground,
                                "beta": pt.beta, "value": pt.value, "state": x,
                                "start": start})  # fmt: skip
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    cfg = WalkConfig()
    dt_half = ModelParams().numerics.dt / 2
    states = walk_only_states()
    tasks = []
    for s in states:
        params = ModelParams.of(ground="penalty") if s["ground"] == "penalty" else ModelParams()
        template = RunTemplate.model_validate({s["param"]: s["value"]})
        spec = template.spec(beta=s["beta"], d31_init=s["start"], duration_s=cfg.duration_s,
                             stop_if_settled_s=cfg.try_s)  # fmt: skip
        tasks.append((run_task(spec, params), run_task(spec.model_copy(update={"dt_s": dt_half}),
                                                       params)))  # fmt: skip
    backend = get_backend("local", args.workers)
    try:
        results, stats = run_tasks([t for pair in tasks for t in pair],
                                   ResultCache(default_cache_dir()), backend)  # fmt: skip
    finally:
        backend.close()
    held = 0
    for s, (full, half) in zip(states, tasks, strict=True):
        a, b = results[full.key], results[half.key]
        sa, sb = settling(list(a.get("d31") or [])), settling(list(b.get("d31") or []))
        s |= {"final": sa.final, "settled": sa.settled, "landing": a.get("landing_swing_share"),
              "final_dt2": sb.final, "settled_dt2": sb.settled,
              "why_dt2": sb.why or b.get("error")}  # fmt: skip
        s["holds"] = bool(sb.settled and sb.final is not None and sa.final is not None
                          and abs(sb.final - sa.final) <= SAME_RAD)  # fmt: skip
        held += s["holds"]
        print(f"{s['axis']} {s['ground']} beta {s['beta']:g} {s['param']} {s['value']:g}: "
              f"{s['state']:.3f} from {s['start']:.2f}; "
              f"landing {s['landing'] or float('nan'):.2f}; "
              f"dt/2 {s['final_dt2'] if s['final_dt2'] is None else round(s['final_dt2'], 3)} "
              f"{'settled' if s['settled_dt2'] else 'not settled: ' + str(s['why_dt2'])[:50]}"
              f"{'' if s['holds'] else '  <- differs'}")  # fmt: skip
    print(
        f"{held} of {len(states)} walk-only states hold at dt/2 within {SAME_RAD} rad; "
        f"{stats.computed} walks computed, {stats.cached} cached"
    )
    out = ROOT / "docs" / "data" / "atlas_walk_states_dt2.json"
    out.write_text(json.dumps({"same_rad": SAME_RAD, "held": held, "states": states}, indent=1))


if __name__ == "__main__":
    main()

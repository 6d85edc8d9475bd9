"""Sixth campaign: which of a candidate's coordinates move its folds? (issue 52, a diagnostic
before the local refinement)

    python -m lab.campaigns.campaign6_levers --trial 78
    python -m lab.campaigns.campaign6_levers --trial 78 --scale 0.1   # the +-10% check

One coordinate at a time, a step down and a step up from the candidate (`STEP` of the search
box's width, on the log axis for log ranges; clipped to the box), each variant scored by the
sixth campaign's full walk objective (`lab.walk_objective.evaluate_walks`, the search's ten 16 s
walks, through its cache). Prints, per coordinate, the two variants' folds, the walks against
the paper and the scores beside the candidate's, and writes them to `--out` (JSON), resumable
(variants already written are not walked again). With `--scale s`, each coordinate is instead
multiplied by 1 - s and 1 + s (not clipped to the box): the +-10% check a claim needs.

Why: #78 (soft regime) has the paper's metachronal fold and the jump from it to the tripod but
keeps the tripod up to 0.70; a lever that ends the tripod near 0.67 without losing the jump is
what a local refinement should follow, and the scan says which levers are worth its dimensions.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path
from typing import Any

from lab.calibrate import reachable
from lab.campaigns.campaign6_confirm import trial_values
from lab.campaigns.campaign6_search import _space, params_of
from lab.space import Range
from lab.walk_objective import evaluate_walks
from sim_core import ResultCache, get_backend

STEP = 0.2  # of the box's width (log width for log ranges): a lever, not a +-10% check


def stepped(value: float, r: Range, sign: int) -> float:
    """`value` moved `sign * STEP` of the box's width, clipped to the box."""
    if r.log:
        x = math.log(value) + sign * STEP * (math.log(r.high) - math.log(r.low))
        return min(r.high, max(r.low, math.exp(x)))
    return min(r.high, max(r.low, value + sign * STEP * (r.high - r.low)))


def summary(score: Any) -> dict[str, Any]:
    a = score.attrs()
    keep = ("metachronal_fold", "tripod_fold", "against_paper", "metachronal_value",
            "tripod_value", "speed_ratio", "slip", "landing_share", "walks")  # fmt: skip
    return {k: a[k] for k in keep} | {"score": score.score}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trial", type=int, required=True)
    ap.add_argument("--only", default="", help="comma-separated coordinates (default: all)")
    ap.add_argument(
        "--values",
        action="append",
        default=[],
        help="name=v1,v2,...: a scan of one coordinate at these values instead",
    )
    ap.add_argument("--scale", type=float, default=None, help="s: each coordinate x (1 -+ s)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cache", default="out/campaign6/cache")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    kind = "levers" if a.scale is None else f"pm{round(100 * a.scale)}"
    out = Path(a.out or f"docs/data/campaign6_{kind}_{a.trial}.json")
    done: dict[str, Any] = json.loads(out.read_text()) if out.exists() else {}
    base = trial_values(a.trial)
    backend, cache = get_backend("local", a.workers), ResultCache(a.cache)
    space = _space(base["ground"])
    names = [n for n in space if not a.only or n in a.only.split(",")]
    if "base" not in done:
        done["base"] = {"values": base, **summary(evaluate_walks(params_of(base), cache, backend))}
    variants: list[tuple[str, str, float]] = [
        (f"{n}{'-' if sign < 0 else '+'}", n,
         stepped(float(base[n]), space[n], sign) if a.scale is None
         else float(base[n]) * (1 + sign * a.scale))
        for n in names for sign in (-1, 1)
    ] if not a.values else [
        (f"{n}={v}", n, float(v)) for item in a.values
        for n, vs in [item.split("=")] for v in vs.split(",")
    ]  # fmt: skip
    for key, name, value in variants:
        if key in done:
            continue
        values = dict(base)
        values[name] = value
        t0 = time.perf_counter()
        try:
            params = params_of(values)
            ok = reachable(params)
        except ValueError:
            ok = False
        row: dict[str, Any] = {"name": name, "value": values[name], "from": base[name]}
        if ok:
            row |= summary(evaluate_walks(params, cache, backend))
        else:
            row["error"] = "not walkable (a tip target out of reach or invalid)"
        row["wall_s"] = round(time.perf_counter() - t0, 1)
        done[key] = row
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(json.dumps(done, indent=1))
        f_m, f_t = row.get("metachronal_fold"), row.get("tripod_fold")
        print(f"{key:28s} {row['value']:.4g} (from {base[name]:.4g}): "
                  + (row.get("error") or f"folds M {f_m:.4f} T {f_t:.4f} against "
                     f"{row['against_paper']} score {row['score']:.4f}")
                  + f" [{row['wall_s']} s]", flush=True)  # fmt: skip
    b = done["base"]
    print(f"base: folds M {b['metachronal_fold']:.4f} T {b['tripod_fold']:.4f} "
          f"score {b['score']:.4f}; wrote {out}")  # fmt: skip


if __name__ == "__main__":
    main()

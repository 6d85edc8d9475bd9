"""Sixth campaign, point 4's first checks (issue 52): do a search candidate's 16 s readings
hold as settled 40 s walks, at dt and at dt/2?

    python -m lab.campaigns.campaign6_confirm --trial 78
    python -m lab.campaigns.campaign6_confirm --trial 78 --scale kp_lift=1.1 --no-half-dt

For one candidate of `docs/data/campaign6_trials.json` (its search coordinates, optionally with
coordinates scaled by `--scale name=factor` or set by `--set name=value`, as the +-10% checks
need), walks from both of the objective's starts (`lab.walk_objective.STARTS`) at `--betas`,
`--seconds` long, at the model's dt and (unless `--no-half-dt`) at dt/2, every run through the
campaign's result cache. Each walk is read with the objective's rule (`read_walk`: holds its
branch or leaves it) and with the core's settled rule (`settling`), with its landing share and
speed against eq. 2; the folds are read from the holds as the objective reads them. Prints a
table and writes the rows to `--out` (JSON).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

from lab.campaigns.campaign6_search import params_of
from lab.walk_objective import fold_from_holds, lives, read_walk, walk_specs
from sim_core import ResultCache, get_backend, nominal_speed, run_task, run_tasks
from sim_core.contract import settling

TRIALS = Path("docs/data/campaign6_trials.json")
BETAS = (0.62, 0.635, 0.645, 0.655, 0.67, 0.685, 0.70)


def trial_values(number: int, path: Path = TRIALS) -> dict[str, Any]:
    """A trial's search coordinates, from the export."""
    rows = json.loads(path.read_text())["trials"]
    return dict(next(r for r in rows if r["number"] == number)["params"])


def changed(values: dict[str, Any], scale: list[str], set_: list[str]) -> dict[str, Any]:
    """`values` with `name=factor` scalings and `name=value` settings applied."""
    out = dict(values)
    for item in scale:
        name, f = item.split("=")
        if name not in out:
            raise SystemExit(f"--scale {name}: not a coordinate of this trial ({sorted(out)})")
        out[name] = float(out[name]) * float(f)
    for item in set_:
        name, v = item.split("=")
        out[name] = v if name in ("ground", "trajectory_frame") else float(v)
    return out


def confirm(
    values: dict[str, Any],
    betas: list[float],
    seconds: float,
    half_dt: bool,
    workers: int,
    cache: str,
) -> list[dict[str, Any]]:
    """The walks' rows (both starts, each beta, dt and optionally dt/2)."""
    params = params_of(values)
    dts: list[float | None] = [None] + ([params.numerics.dt / 2] if half_dt else [])
    specs = [(side, s) for dt in dts for side, s in walk_specs(betas, duration_s=seconds,
                                                               dt_s=dt)]  # fmt: skip
    tasks = [run_task(s, params) for _, s in specs]
    results, _ = run_tasks(tasks, ResultCache(cache), get_backend("local", workers),
                           chunk_size=1, progress="walks")  # fmt: skip
    tr = params.trajectory
    rows = []
    for (side, s), task in zip(specs, tasks, strict=True):
        r = results[task.key]
        v0 = 100 * nominal_speed(s.beta, tr.stroke, tr.swing_duration)
        w = read_walk(side, s.beta, r, v0)
        st = None if w.failed else settling(r["d31"])
        rows.append({"side": side, "beta": s.beta, "half_dt": s.dt_s is not None,
                     "final": w.final, "drift": w.drift, "holds": w.holds,
                     "settled": bool(st and st.settled), "paper": lives(side, s.beta),
                     "landing": w.landing_share, "speed_ratio": w.speed_ratio, "slip": w.slip,
                     "failed": w.failed})  # fmt: skip
    return rows


def folds(rows: list[dict[str, Any]], half_dt: bool) -> dict[str, float]:
    """Both folds read from the holds (as the objective reads them) at one step."""
    out = {}
    for side, rising in (("metachronal", True), ("tripod", False)):
        rs = sorted((r for r in rows if r["side"] == side and r["half_dt"] == half_dt),
                    key=lambda r: r["beta"])  # fmt: skip
        fold, miss = fold_from_holds([r["beta"] for r in rs], [r["holds"] for r in rs], rising)
        out[side] = fold
        out[f"{side}_mismatches"] = miss
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trial", type=int, required=True)
    ap.add_argument("--scale", action="append", default=[], help="name=factor")
    ap.add_argument("--set", action="append", default=[], help="name=value")
    ap.add_argument("--betas", default=",".join(map(str, BETAS)))
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--no-half-dt", action="store_true")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cache", default="out/campaign6/cache")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    values = changed(trial_values(a.trial), a.scale, a.set)
    betas = [float(x) for x in a.betas.split(",")]
    t0 = time.perf_counter()
    rows = confirm(values, betas, a.seconds, not a.no_half_dt, a.workers, a.cache)
    wall = time.perf_counter() - t0
    print("| beta | from | step | final | drift (mrad/cycle) | holds | settled | landing | speed |"
          "\n|---|---|---|---|---|---|---|---|---|")  # fmt: skip
    for r in sorted(rows, key=lambda r: (r["half_dt"], r["side"], r["beta"])):
        fin = "failed" if r["final"] is None else f"{r['final']:.3f}"
        dr = "" if r["drift"] is None else f"{1e3 * r['drift']:+.2f}"
        land = "" if r["landing"] is None else f"{r['landing']:.2f}"
        sp = "" if r["speed_ratio"] is None else f"{r['speed_ratio']:.3f}"
        step, holds = "dt/2" if r["half_dt"] else "dt", "holds" if r["holds"] else "leaves"
        print(f"| {r['beta']} | {r['side']} | {step} | {fin} | {dr} | {holds} | {r['settled']} "
              f"| {land} | {sp} |")  # fmt: skip
    steps = [False] + ([True] if not a.no_half_dt else [])
    found = {("dt/2" if h else "dt"): folds(rows, h) for h in steps}
    print(f"folds (holds' best split): {found}; {wall:.0f} s")
    out = Path(a.out or f"out/campaign6/confirm_{a.trial}"
               + "".join(f"_{x}" for x in a.scale + a.set) + ".json")  # fmt: skip
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"trial": a.trial, "scale": a.scale, "set": a.set,
                               "values": values, "seconds": a.seconds, "folds": found,
                               "wall_s": wall, "rows": rows}, indent=1))  # fmt: skip
    print(f"wrote {out}")


if __name__ == "__main__":
    main()

"""Validate the sixth campaign's walk objective (`lab.walk_objective`) before it searches:
does a short walk's "holds / leaves" agree with the same walk read at 40 s, in both regimes?

    python -m lab.campaigns.walk_objective_check [OUT.json]

Runs 40 s walks from both of the paper's branch values at `WALK_BETAS` for the defaults (the
stiff regime), the soft legs, the soft legs with stiffer middle legs (support ratio 3.5,
../shared/notes/two-regimes.md) and campaign 5's two best candidates (#180, #283, whose
pinned surfaces had a loop the walks did not), and reads each walk's prefix of 8, 12, 16 and
24 s with the objective's rule against its whole 40 s. Every run goes through the result
cache (out/campaign6/cache), so a rerun reads it back. Writes the rows (default
docs/studies/walk_objective_check.json) and prints the agreement per prefix and a table.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from lab.campaigns.campaign5_search import STUDY as CAMPAIGN5
from lab.surface_search import geometry
from lab.walk_objective import WALK_BETAS, lives, read_walk, walk_specs
from sim_core import ModelParams, ResultCache, get_backend, run_task, run_tasks
from sim_core.contract import settling
from sim_core.research import named_params

TRIALS = Path("docs/data/campaign5_trials.json")
PREFIXES_S = (8.0, 12.0, 16.0, 24.0)
TRUTH_S = 40.0


def settings() -> dict[str, ModelParams]:
    rows = {r["number"]: r for r in json.loads(TRIALS.read_text())["trials"]}
    out = {
        "defaults": ModelParams(),
        "soft_legs": named_params("soft_legs"),
        "soft_legs, support 3.5": named_params("soft_legs", support_ratio=3.5),
    }
    for n in (180, 283):
        values = dict(rows[n]["params"])
        out[f"{CAMPAIGN5} #{n}"] = ModelParams.of(**geometry(values))
    return out


def prefix(result: dict[str, Any], t_s: float) -> dict[str, Any]:
    """The result as a run `t_s` long would have given its Delta31 series."""
    t = np.asarray(result["d31_times_s"])
    return {"d31": list(np.asarray(result["d31"])[t <= t_s])}


def main() -> None:
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "docs/studies/walk_objective_check.json")
    backend, cache = get_backend("local", 2), ResultCache("out/campaign6/cache")
    rows: list[dict[str, Any]] = []
    walls: dict[str, float] = {}
    for name, p in settings().items():
        specs = walk_specs(WALK_BETAS, duration_s=TRUTH_S)
        tasks = [run_task(s, p) for _, s in specs]
        t0 = time.perf_counter()
        results, _ = run_tasks(tasks, cache, backend, chunk_size=1, progress=name)
        walls[name] = time.perf_counter() - t0
        for (side, s), task in zip(specs, tasks, strict=True):
            r = results[task.key]
            truth = read_walk(side, s.beta, r, 1.0)
            st = None if truth.failed else settling(r["d31"])
            row: dict[str, Any] = {
                "setting": name, "side": side, "beta": s.beta,
                "final_40": truth.final, "drift_40": truth.drift, "holds_40": truth.holds,
                "settled_40": bool(st and st.settled), "paper": lives(side, s.beta),
                "landing": r.get("landing_swing_share"),
            }  # fmt: skip
            for t_s in PREFIXES_S:
                w = read_walk(side, s.beta, prefix(r, t_s), 1.0) if not truth.failed else truth
                row[f"holds_{t_s:g}"] = w.holds
                row[f"final_{t_s:g}"] = w.final
                row[f"drift_{t_s:g}"] = w.drift
            rows.append(row)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"wall_s": walls, "rows": rows}, indent=1))
    print("prefix | agrees with 40 s | disagreements")
    for t_s in PREFIXES_S:
        bad = [r for r in rows if r[f"holds_{t_s:g}"] != r["holds_40"]]
        where = ", ".join(f"{r['setting']} {r['side'][0]} {r['beta']}" for r in bad)
        print(f"{t_s:g} s | {len(rows) - len(bad)} of {len(rows)} | {where}")
    print("\n| setting | beta | from | 16 s: final, drift (mrad/cycle), holds | 40 s: final, "
          "drift, holds, settled | paper |\n|---|---|---|---|---|---|")  # fmt: skip

    def cell(r: dict[str, Any], k: str) -> str:
        f, d = r[f"final_{k}"], r[f"drift_{k}"]
        if f is None or d is None:
            return "failed"
        return f"{f:.3f}, {1e3 * d:+.2f}, {'holds' if r[f'holds_{k}'] else 'leaves'}"

    for r in rows:
        print(f"| {r['setting']} | {r['beta']} | {r['side']} | {cell(r, '16')} | "
              f"{cell(r, '40')}, {'settled' if r['settled_40'] else 'not settled'} | "
              f"{'lives' if r['paper'] else 'absent'} |")  # fmt: skip
    print(f"\nwall: {walls}")


if __name__ == "__main__":
    main()

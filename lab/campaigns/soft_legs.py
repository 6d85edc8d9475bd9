"""The soft-leg regime (`named_params("soft_legs")`) re-measured with the project's tools
(issue 52, point 2): settled 40 s walks from Delta31 1.9 across the metachronal end and from
3.0 for the upper state, at the default step and at dt/2.

Usage: python -m lab.campaigns.soft_legs [OUT.json]  (default docs/studies/soft_legs.json)
Prints a markdown table; each row: the final (mean of the last quarter), the settled rule's
verdict and drift per cycle, the landing share, slip and speed.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Any

from sim_core import RunSpec, simulate_batch
from sim_core.contract import settling
from sim_core.research import named_params

FROM_19 = (0.62, 0.6375, 0.64, 0.645, 0.65, 0.66, 0.70)  # across the metachronal end
FROM_30 = (0.62, 0.66, 0.70)  # the upper state
DURATION_S = 40.0
DT_S = {"dt": None, "dt/2": 2.5e-5}


def rows(label: str, dt_s: float | None) -> tuple[list[dict[str, Any]], float]:
    specs = [RunSpec(beta=b, d31_init=1.9, duration_s=DURATION_S, dt_s=dt_s) for b in FROM_19]
    specs += [RunSpec(beta=b, d31_init=3.0, duration_s=DURATION_S, dt_s=dt_s) for b in FROM_30]
    t = time.perf_counter()
    runs = simulate_batch(specs, named_params("soft_legs"), nthread=2)
    wall = time.perf_counter() - t
    out: list[dict[str, Any]] = []
    for s, r in zip(specs, runs, strict=True):
        m = r.measures
        st = None if r.failure else settling(r.events.d31)
        out.append({"step": label, "beta": s.beta, "start": s.d31_init, "final": m.d31_final,
                    "gait": m.gait, "settled": bool(st and st.settled),
                    "drift_mrad_per_cycle": None if st is None or st.drift is None
                    else 1e3 * st.drift,
                    "landing": m.landing_swing_share, "slip": m.slip_fraction,
                    "speed_cm_s": m.speed_cm_s,
                    "failure": r.failure.kind if r.failure else None})  # fmt: skip
    return out, wall


def main() -> None:
    path = Path(sys.argv[1] if len(sys.argv) > 1 else "docs/studies/soft_legs.json")
    table: list[dict[str, Any]] = []
    walls = {}
    for label, dt in DT_S.items():
        r, walls[label] = rows(label, dt)
        table += r
        print(f"{label}: {len(r)} runs of {DURATION_S:g} s in {walls[label]:.0f} s", flush=True)
    path.write_text(json.dumps({"setting": "soft_legs", "wall_s": walls, "rows": table}, indent=1))
    print("| step | beta | from | final | gait | settled (drift mrad/cycle) | landing | slip | "
          "speed cm/s |\n|---|---|---|---|---|---|---|---|---|")  # fmt: skip
    for x in table:
        d = x["drift_mrad_per_cycle"]
        drift = "" if d is None else f" ({d:+.2f})"
        print(
            f"| {x['step']} | {x['beta']} | {x['start']} | {x['final']:.3f} | {x['gait']} | "
            f"{'yes' if x['settled'] else 'no'}{drift} | {x['landing']:.2f} | "
            f"{100 * x['slip']:.1f}% | {x['speed_cm_s']:.2f} |"
        )


if __name__ == "__main__":
    main()

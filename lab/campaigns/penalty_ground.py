"""The penalty ground's settled finals at dt, dt/2 and RK4 2e-5 s (docs/NUMERICS.md).

Usage: K=2000 LABELS=default,half,rk4 python -m lab.campaigns.penalty_ground
Beta 0.62 and 0.70 from Delta31 1.9 and 3.0, 30 s each; writes out/penalty_ground_K_LABELS.json.
VARY=ground_damping:1.1 scales one more field (the +-10% check).
"""

import json
import os
import time
from pathlib import Path

from sim_core import ModelParams, RunSpec, simulate_batch
from sim_core.contract import settling

K = float(os.environ.get("K", "2000"))
C = 0.1 * (K / 2000) ** 0.5  # the same damping ratio as 0.1 N s/m at 2000 N/m
LABELS = os.environ.get("LABELS", "default,half,rk4").split(",")
VARY = os.environ.get("VARY", "")
STEPS = {"default": (None, None), "half": (None, 2.5e-5), "rk4": ("rk4", 2e-5)}


def main() -> None:
    p = ModelParams.of(ground="penalty", ground_stiffness=K, ground_tangential_stiffness=K,
                    ground_damping=C, ground_tangential_damping=C)  # fmt: skip
    if VARY:
        field, factor = VARY.split(":")
        p = p.replace(**{field: p.leaf(field) * float(factor)})
    out = {}
    for label in LABELS:
        integ, dt = STEPS[label]
        specs = [RunSpec(beta=b, d31_init=x, duration_s=30.0, integrator=integ, dt_s=dt)
                 for b in (0.62, 0.70) for x in (1.9, 3.0)]  # fmt: skip
        t = time.perf_counter()
        runs = simulate_batch(specs, p, nthread=2)
        wall = time.perf_counter() - t
        rows = []
        for s, r in zip(specs, runs, strict=True):
            td = None if r.failure else settling(r.events.d31)
            m = r.measures
            rows.append({"beta": s.beta, "start": s.d31_init, "final": m.d31_final,
                         "gait": m.gait, "drift": None if td is None else td.drift,
                         "slip": m.slip_fraction, "landing": m.landing_swing_share,
                         "retouch": m.retouches_per_stance, "speed": m.speed_cm_s,
                         "failure": r.failure and r.failure.kind})  # fmt: skip
        out[label] = {"wall_s": wall, "rows": rows}
        print(label, f"{wall:.0f} s", [(x["beta"], x["start"], x["final"]) for x in rows])
    Path("out").mkdir(exist_ok=True)
    Path(f"out/penalty_ground_{K:g}_{'-'.join(LABELS)}{VARY.replace(':', '')}.json").write_text(
        json.dumps(out, indent=1)
    )


if __name__ == "__main__":
    main()

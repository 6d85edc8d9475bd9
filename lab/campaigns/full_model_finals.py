"""Fourth study (docs/studies/journal.md): where 12 starts of the full model end, per beta.

    python -m lab.campaigns.full_model_finals '{"tarsus_stiffness": 15,
        "tarsus_damping": 0.04, "swing_height": 0.001}' --betas 0.62 0.70 --duration-s 5 \
        [--dt-s 2.5e-5]

Prints the final Delta31 of each start, the median slip (share of the stroke), the median
speed and where in the swing the feet land (`RunMeasures.landing_swing_share`, the median over
the runs; 1 = at the AEP, 0.5 = when the scuff window closes): an attractor reached with feet
landing in mid-swing is set by the swing and scuff rule, not by walking mechanics.
`--plot FILE` draws Delta31 per gait cycle, one panel per beta, with
`sim_core.research.fig5` (the reproduction's Fig. 5 drawing).
A scratch study tool kept so that the numbers in the docs can be re-made; the product's
own commands (`python -m lab study`, `reproduce`) are the supported path.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from sim_core import ModelParams, RunSpec, simulate_batch
from sim_core.research import fig5


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("overrides", nargs="?", default="{}", help="ModelParams fields as JSON")
    ap.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.70])
    ap.add_argument("--duration-s", type=float, default=5.0)
    ap.add_argument("--dt-s", type=float, default=None)
    ap.add_argument("--starts", type=int, default=12)
    ap.add_argument("--plot", default=None, help="PNG: Delta31 per cycle, per beta")
    a = ap.parse_args()
    params = ModelParams().replace(**json.loads(a.overrides))
    n = a.starts
    starts = np.linspace(0, 2 * np.pi, n, endpoint=False) + np.pi / n
    specs = [RunSpec(beta=b, d31_init=float(x), duration_s=a.duration_s, dt_s=a.dt_s)
             for b in a.betas for x in starts]  # fmt: skip
    results = simulate_batch(specs, params)
    for b in a.betas:
        runs = [r for r in results if r.spec.beta == b]
        ok = [r for r in runs if r.error is None]
        finals = [round(float(r.events.d31[-1]), 2) if r.error is None else "failed" for r in runs]
        slip = np.median(
            [r.measures.slip_fraction for r in ok if r.measures.slip_fraction is not None]
        )
        speed = np.median([r.measures.speed_cm_s for r in ok if r.measures.speed_cm_s is not None])
        land = np.median(
            [
                r.measures.landing_swing_share
                for r in ok
                if r.measures.landing_swing_share is not None
            ]
        )
        print(
            f"beta {b}: finals {finals}  slip {slip:.3f}  speed {speed:.2f} cm/s  "
            f"feet land at {land:.2f} of the swing"
        )
    if a.plot:
        series = [{"beta": r.spec.beta, "d31_init": r.spec.d31_init, "d31": r.events.d31.tolist(),
                   "error": r.error} for r in results]  # fmt: skip
        fig5({"runs": series}, Path(a.plot))


if __name__ == "__main__":
    main()

"""The issue's 're-spelled' variant: the constraint contact with solref given as direct
stiffness and damping (negative solref), equivalent to today's (timeconst, dampratio), timed
side by side with today's contact and the penalty ground (docs/MODEL.md, the ground section).

    python -m lab.campaigns.ground_respelled

The variant model goes in through `BatchRunner`'s `build` seam (the model builder it compiles
with), not by patching the runner module.
"""

from __future__ import annotations

import time

import mujoco
import numpy as np

from sim_core import ModelParams, RunResult, RunSpec
from sim_core.research import BatchRunner, build_model


def direct(
    params: ModelParams | None = None, slope_deg: float = 0.0, visual: bool = True
) -> mujoco.MjModel:
    """Today's model with the feet's solref re-spelled as (-k, -b) from (timeconst, dampratio)."""
    m = build_model(params, slope_deg, visual)
    p = params or ModelParams()
    if p.contact.ground == "constraint":
        tc, dr, dmax = (
            p.contact.contact_timeconst,
            p.contact.contact_dampratio,
            p.contact.contact_dmax,
        )
        k = 1.0 / (dmax * dmax * tc * tc * dr * dr)  # MuJoCo: aref = -b v - k r, from (tc, dr)
        b = 2.0 / (dmax * tc)
        feet = [g for g in range(m.ngeom) if m.geom_contype[g] == 1]
        m.geom_solref[feet] = [-k, -b]
    return m


def rate(p: ModelParams, spec: RunSpec, respelled: bool) -> tuple[float, RunResult]:
    """Simulated seconds per wall second of one run (after its first, compiling, period)."""
    r = BatchRunner([spec], p, nthread=1, build=direct if respelled else build_model)
    r.run(max_blocks=1)
    t = time.perf_counter()
    r.run()
    w = time.perf_counter() - t
    return (r.time - r.control_dt) / w, r.result(0)


def finals(specs: list[RunSpec], respelled: bool) -> list[float]:
    r = BatchRunner(specs, nthread=2, build=direct if respelled else build_model)
    r.run()
    return [
        np.nan if (f := r.result(i).measures.d31_final) is None else f for i in range(len(specs))
    ]


def main() -> None:
    spec = RunSpec(beta=0.66, d31_init=2.5, duration_s=3.0)
    for rep in range(2):
        for name, p, respelled in (
            ("constraint (timeconst, dampratio)", ModelParams(), False),
            ("constraint (solref as -k, -b)", ModelParams(), True),
            ("penalty ground", ModelParams.of(ground="penalty"), False),
        ):
            x, res = rate(p, spec, respelled)
            m = res.measures
            print(rep, f"{name:36s} {x:5.2f} x real time, final {m.d31_final}, {m.gait}")
    # outcome equality of the re-spelling at beta 0.62 / 0.70 from 1.9 / 3.0, 10 s
    specs = [RunSpec(beta=b, d31_init=x, duration_s=10.0) for b in (0.62, 0.7) for x in (1.9, 3.0)]
    print("finals timeconst:", np.round(finals(specs, False), 4).tolist())
    print("finals direct:   ", np.round(finals(specs, True), 4).tolist())


if __name__ == "__main__":
    main()

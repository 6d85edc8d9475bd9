"""The issue's 're-spelled' variant: the constraint contact with solref given as direct
stiffness and damping (negative solref), equivalent to today's (timeconst, dampratio), timed
side by side with today's contact and the penalty ground (study script, not product code)."""

import time

import numpy as np

import sim_core.model.runner as runner_mod
from sim_core import ModelParams, RunSpec, simulate_batch
from sim_core.model import mjspec

orig = mjspec.build_model


def direct(params=None, slope_deg=0.0, visual=True):
    m = orig(params, slope_deg, visual)
    p = params or ModelParams()
    if p.ground == "constraint":
        tc, dr, dmax = p.contact_timeconst, p.contact_dampratio, p.contact_dmax
        k = 1.0 / (dmax * dmax * tc * tc * dr * dr)  # MuJoCo: aref = -b v - k r, from (tc, dr)
        b = 2.0 / (dmax * tc)
        feet = [g for g in range(m.ngeom) if m.geom_contype[g] == 1]
        m.geom_solref[feet] = [-k, -b]
    return m


def rate(p, spec, patched):
    runner_mod.build_model = direct if patched else orig
    r = runner_mod.BatchRunner([spec], p, nthread=1)
    r.run(max_blocks=1)
    t = time.perf_counter()
    r.run()
    w = time.perf_counter() - t
    return (r.time - r.control_dt) / w, r.result(0)


spec = RunSpec(beta=0.66, d31_init=2.5, duration_s=3.0)
for rep in range(2):
    for name, p, patched in (
        ("constraint (timeconst, dampratio)", ModelParams(), False),
        ("constraint (solref as -k, -b)", ModelParams(), True),
        ("penalty ground", ModelParams(ground="penalty"), False),
    ):
        x, res = rate(p, spec, patched)
        print(rep, f"{name:36s} {x:5.2f} x real time, final {res.d31_final:.4f}, {res.gait}")
# outcome equality of the re-spelling at beta 0.62 / 0.70 from 1.9 / 3.0, 10 s
runner_mod.build_model = orig

specs = [RunSpec(beta=b, d31_init=x, duration_s=10.0) for b in (0.62, 0.7) for x in (1.9, 3.0)]
a = [r.d31_final for r in simulate_batch(specs, nthread=2)]
runner_mod.build_model = direct
bb = [r.d31_final for r in simulate_batch(specs, nthread=2)]
print("finals timeconst:", np.round(a, 4).tolist())
print("finals direct:   ", np.round(bb, 4).tolist())

"""Walk once, until settled, and print what the run measured: Delta31, the gait, the speed.

python examples/01_walk_once.py --beta 0.62 --d31-init 2.0
"""

import argparse

from sim_core import RunSpec, nominal_speed, simulate_batch
from sim_core.cli.walk import SETTLE_CAP_S, SETTLE_TRY_S  # `insect-gait run`'s "until settled"

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--beta", type=float, default=0.62, help="duty factor (0.5, 1)")
parser.add_argument("--d31-init", type=float, default=2.0, help="initial Delta31, rad")
parser.add_argument("--duration-s", type=float, default=None,
                    help=f"simulated seconds (default: stop at {SETTLE_TRY_S:g} s if settled, "
                    f"else go on to {SETTLE_CAP_S:g} s)")  # fmt: skip
args = parser.parse_args()

fields = {"duration_s": SETTLE_CAP_S, "stop_if_settled_s": SETTLE_TRY_S}
if args.duration_s is not None:
    fields = {"duration_s": args.duration_s}
spec = RunSpec(beta=args.beta, d31_init=args.d31_init, **fields)
(result,) = simulate_batch([spec], nthread=1, progress=True)  # a batch of one: a progress bar
if result.error:
    raise SystemExit(f"the run failed: {result.error}")
m = result.measures
print(
    "Delta31 at leg-1 touchdowns: " + " ".join(f"{x:.2f}" for x in result.events.d31[:12]) + " ..."
)
end = "n/a" if m.d31_final is None else f"{m.d31_final:.3f} rad"
print(f"after {m.duration_s:g} s ends at {end}: {m.gait} ({m.settled_why or 'settled'})")
v_eq2 = nominal_speed(args.beta, 2e-3, 34e-3) * 100  # D = 2 mm, T_sw = 34 ms
print(f"speed {m.speed_cm_s:.2f} cm/s (eq. 2: {v_eq2:.2f})")
print(f"feet land at {m.landing_swing_share:.2f} of the swing (1 = at the AEP)")

"""A live simulation (the viewer's engine): settle, then ramp beta down and back up.

python examples/03_live_beta_ramp.py --settle-s 5 --ramp-s 20
"""

import argparse

from sim_core import RunSpec, Simulation

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--settle-s", type=float, default=5.0, help="seconds at the start beta")
parser.add_argument("--ramp-s", type=float, default=20.0, help="seconds for each ramp leg")
parser.add_argument("--high", type=float, default=0.70)
parser.add_argument("--low", type=float, default=0.62)
args = parser.parse_args()

sim = Simulation(RunSpec(beta=args.high, d31_init=1.9))
print(f"settling {args.settle_s:g} s at beta {args.high:.3f} from Delta31 1.9 ...", flush=True)
print("(the gait is the live label: the footfall of the last three cycles, or 'changing' while")
print(" Delta31 drifts faster than the settled rule allows, as it may while beta moves)")
sim.advance(args.settle_s)
steps = 20
for leg, (a, b) in enumerate(((args.high, args.low), (args.low, args.high))):
    for k in range(1, steps + 1):
        sim.set_beta(a + (b - a) * k / steps)
        sim.advance(args.ramp_s / steps)
        d31 = sim.d31_events[-1][1] if sim.d31_events else float("nan")
        print(
            f"{'down' if leg == 0 else 'up  '} beta {sim.beta:.3f}  Delta31 {d31:.2f}  {sim.gait}",
            flush=True,
        )

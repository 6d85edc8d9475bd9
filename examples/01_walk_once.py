"""Walk once and print what the run measured: Delta31 per gait cycle, the gait, the speed.

python examples/01_walk_once.py --beta 0.62 --d31-init 2.0 --duration-s 5
"""

import argparse

from sim_core import RunSpec, nominal_speed, simulate

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--beta", type=float, default=0.62, help="duty factor (0.5, 1)")
parser.add_argument("--d31-init", type=float, default=2.0, help="initial Delta31, rad")
parser.add_argument("--duration-s", type=float, default=5.0, help="simulated seconds")
args = parser.parse_args()

result = simulate(RunSpec(beta=args.beta, d31_init=args.d31_init, duration_s=args.duration_s))
if result.error:
    raise SystemExit(f"the run failed: {result.error}")
summary = result.summary()
print(f"Delta31 at leg-1 touchdowns: {[round(x, 2) for x in summary['d31'][:12]]} ...")
end = "n/a" if summary["d31_final"] is None else f"{summary['d31_final']:.3f} rad"
print(f"ends at {end}: {summary['gait']} ({summary['settled_why'] or 'settled'})")
v_eq2 = nominal_speed(args.beta, 2e-3, 34e-3) * 100  # D = 2 mm, T_sw = 34 ms
print(f"speed {summary['speed_cm_s']:.2f} cm/s (eq. 2: {v_eq2:.2f})")
print(f"feet land at {result.measures.landing_swing_share:.2f} of the swing (1 = at the AEP)")

"""A return map at one beta (the paper's Fig. 7 construction) and its plot.

Delta31(n) against Delta31(n+4) at leg-1 touchdowns from starts spread over the circle; where
the smoothed drift per cycle crosses zero going down is a stable gait.

    python examples/02_return_map.py --beta 0.66 --out return_map.png
"""

import argparse
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from sim_core.paper.analysis import summarise_map
from sim_core.paper.protocols import initial_values, return_map

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--beta", type=float, default=0.66)
parser.add_argument("--starts", type=int, default=12, help="initial Delta31 values")
parser.add_argument("--duration-s", type=float, default=3.0, help="per start")
parser.add_argument("--out", default="return_map.png")
args = parser.parse_args()

rm = return_map(None, beta=args.beta, inits=initial_values(args.starts), duration_s=args.duration_s)
fixed = summarise_map(rm, bandwidth=0.13).fixed  # kernel-smoothed drift, as reproduce
print(
    f"{rm.x.size} pairs; fixed points: "
    + ", ".join(f"{f.d31:.2f} ({'stable' if f.stable else 'unstable'})" for f in fixed)
    or "none"
)
fig, ax = plt.subplots(figsize=(4.5, 4.5))
ax.plot(rm.x, rm.y, ".", ms=3)
ax.plot([0, 2 * math.pi], [0, 2 * math.pi], "k-", lw=0.8)
for f in fixed:
    ax.plot(f.d31, f.d31, "o", mfc="k" if f.stable else "w", mec="k")
ax.set(xlabel="Delta31 n (rad)", ylabel="Delta31 n+4 (rad)", title=f"beta = {args.beta}")
fig.savefig(args.out, dpi=110)
print(f"wrote {args.out}")

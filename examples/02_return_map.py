"""Fig. 7 at one beta: where settled walks from a few starts end, and their return map.

At beta 0.62 the starts 1.6, 2.0 and 3.0 reach the metachronal states near 1.77 and 2.12 and
the tripod near 2.95 (the full search, `insect-gait finder`, spreads 8 starts and kicks every
state: minutes). .venv/bin/python examples/02_return_map.py --beta 0.62 --out return_map.png
"""

import argparse
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from sim_core import RunSpec, return_map_from_series, simulate_batch

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--beta", type=float, default=0.62)
parser.add_argument("--starts", type=float, nargs="+", default=[1.6, 2.0, 3.0], help="rad")
parser.add_argument("--duration-s", type=float, default=20.0, help="per start (>= ~15 s to settle)")
parser.add_argument("--out", default="return_map.png")
args = parser.parse_args()

specs = [RunSpec(beta=args.beta, d31_init=x, duration_s=args.duration_s) for x in args.starts]
runs = simulate_batch(specs, progress=True)
ends = {}  # settled end (rad) -> gait
for x, r in zip(args.starts, runs, strict=True):
    m = r.measures
    if m.settled and m.d31_final is not None:
        ends[round(m.d31_final, 2)] = m.gait
    print(f"from {x:.2f} rad: " + (r.error or f"{m.gait} at {m.d31_final:.3f} rad"
          + ("" if m.settled else f" ({m.settled_why})")))  # fmt: skip
print("found: " + (", ".join(f"{g} {x:.2f}" for x, g in sorted(ends.items())) or "none settled"))
rm = return_map_from_series(args.beta, [r.events.d31 for r in runs])
fig, ax = plt.subplots(figsize=(4.5, 4.5))
ax.plot(rm.x, rm.y, ".", ms=3)
ax.plot([0, 2 * math.pi], [0, 2 * math.pi], "k-", lw=0.8)
for x in ends:
    ax.plot(x, x, "o", mfc="k", mec="k")
ax.set(xlabel="Delta31 n (rad)", ylabel="Delta31 n+4 (rad)", title=f"beta = {args.beta}")
fig.savefig(args.out, dpi=110)
print(f"wrote {args.out}")

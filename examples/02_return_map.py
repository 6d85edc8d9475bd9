"""Fig. 7 at one beta from settled walking: the fixed-point finder `reproduce` uses.

.venv/bin/python examples/02_return_map.py --beta 0.62 --out return_map.png
"""

import argparse
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from sim_core import RunSpec, simulate_batch
from sim_core.contract import Cell, FinderConfig, find, return_map_from_series

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--beta", type=float, default=0.62)
parser.add_argument("--starts", type=int, default=8, help="starts spread over the circle")
parser.add_argument("--duration-s", type=float, default=40.0, help="per start (40 s: settled)")
parser.add_argument("--out", default="return_map.png")
args = parser.parse_args()
series: list[list[float]] = []


def run(batch):  # the finder's runs, one simulate_batch per round
    res = simulate_batch([RunSpec(**p.spec_fields(), **c.spec_fields()) for c, p in batch])
    series.extend(r.events.d31.tolist() for r in res)
    return [{"d31": r.events.d31.tolist(), "error": r.error, "duration_s": r.measures.duration_s}
            for r in res]  # fmt: skip


cfg = FinderConfig(args.starts, args.duration_s, bisect_duration_s=args.duration_s / 2)
(cell,) = find([Cell(args.beta)], cfg, run)
points = [(a.d31, True) for a in cell.attractors] + [(b.d31, False) for b in cell.borders if b.d31]
print(*(f"{'stable' if s else 'unstable'} at {x:.3f} rad" for x, s in points), sep="\n")
print(f"{len(cell.unsettled)} run(s) did not settle in {args.duration_s:g} s")
rm = return_map_from_series(args.beta, series)
fig, ax = plt.subplots(figsize=(4.5, 4.5))
ax.plot(rm.x, rm.y, ".", ms=3)
ax.plot([0, 2 * math.pi], [0, 2 * math.pi], "k-", lw=0.8)
for x, stable in points:
    ax.plot(x, x, "o", mfc="k" if stable else "w", mec="k")
ax.set(xlabel="Delta31 n (rad)", ylabel="Delta31 n+4 (rad)", title=f"beta = {args.beta}")
fig.savefig(args.out, dpi=110)

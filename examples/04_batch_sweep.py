"""Many simulations at once: where runs from several starts end, at several betas.

python examples/04_batch_sweep.py --betas 0.62 0.66 0.70 --starts 4 --duration-s 8
"""

import argparse

from sim_core import RunResult, simulate_batch, spec_grid
from sim_core.research import initial_values

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.66, 0.70])
parser.add_argument("--starts", type=int, default=4, help="initial Delta31 values per beta")
parser.add_argument("--duration-s", type=float, default=8.0, help="simulated s per run")
args = parser.parse_args()

starts = initial_values(args.starts)
specs = spec_grid(args.betas, starts, duration_s=args.duration_s)
results = simulate_batch(specs, progress=True)  # one mujoco.batch per numerics, every core


def word(r: RunResult) -> str:
    m = r.measures
    if r.error or m.d31_final is None:
        return "failed" if r.error else "n/a"
    return f"{m.d31_final:.2f} {m.gait}" if m.settled else f"{m.d31_final:.2f}~"


print("starts (rad): " + ", ".join(f"{x:.2f}" for x in starts))
for beta in args.betas:
    print(f"beta {beta:.3f} ends: " + ", ".join(word(r) for r in results if r.spec.beta == beta))
why = sorted({r.measures.settled_why for r in results if r.measures.settled_why})
if why:  # the settled rule (docs/MODEL.md) needs ~15-20 s of walking: short runs are not settled
    print(f"~ not settled by the project's rule: where the run was after {args.duration_s:g} s, "
          f"not a gait (e.g. {why[0]})")  # fmt: skip

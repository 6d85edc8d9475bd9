"""Many simulations at once: where runs from several starts end, at several betas.

python examples/04_batch_sweep.py --betas 0.62 0.66 0.70 --starts 6 --duration-s 10
"""

import argparse

from sim_core import RunResult, simulate_batch, spec_grid
from sim_core.paper.protocols import initial_values

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.66, 0.70])
parser.add_argument("--starts", type=int, default=6, help="initial Delta31 values per beta")
parser.add_argument("--duration-s", type=float, default=10.0)
args = parser.parse_args()

specs = spec_grid(args.betas, initial_values(args.starts), duration_s=args.duration_s)
results = simulate_batch(specs)  # one mujoco.batch per numerics, every core
for beta in args.betas:
    ends = [r for r in results if r.spec.beta == beta]

    def word(r: RunResult) -> str:
        m = r.measures
        if r.error or m.d31_final is None:
            return "fail" if r.error else "n/a"
        return f"{m.d31_final:.2f}{'' if m.settled else '~'}"  # ~: not settled by the rule

    shown = ", ".join(word(r) for r in ends)
    print(f"beta {beta:.3f}: {shown}")

"""How the touchdown instant's resolution moves the phase resets, timestep by timestep.

With phase resetting off, Delta31 is held fixed, so every timestep sees the same gait; the mean
phase jump each leg's touchdown would cause (phi_AEP minus the phase at touchdown) and the
Delta31 drift per cycle they imply, 1/4 [(e5 + e6) - (e1 + e2)], can be compared across
timesteps. Printed for the landing instant at the physics step where the touch is sensed and for
the interpolated clearance crossing, side by side.

    .venv/bin/python benchmarks/touchdown_timing.py [--beta 0.62] [--d31 1.9 2.9]
"""

from __future__ import annotations

import argparse

from sim_core import ModelParams
from sim_core.numerics.convergence import drift_rates

DTS = (2e-4, 1e-4, 5e-5, 2.5e-5)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beta", type=float, default=0.62)
    ap.add_argument("--d31", type=float, nargs="+", default=[1.9, 2.9])
    args = ap.parse_args()
    print(f"beta {args.beta}: drift per cycle (rad) implied by the touchdown phase jumps")
    print(f"{'dt (s)':>9} {'d31':>5} {'at the step':>12} {'interpolated':>13}")
    for d31 in args.d31:
        for dt in DTS:
            row = [
                float(drift_rates("implicitfast", dt,
                                  params=ModelParams.of(touchdown_interpolation=interp),
                                  betas=(args.beta,), d31s=(d31,), duration_s=1.5)[0, 0])
                for interp in (False, True)
            ]  # fmt: skip
            print(f"{dt:9.2g} {d31:5.2f} {row[0]:+12.4f} {row[1]:+13.4f}")


if __name__ == "__main__":
    main()

"""The short probes (`SHORT_PROBES`: 0.25 s settle + 0.5 s average) against the 0.5 s + 1 s
ones, read from the same cached runs, per regime (issue 54 item 5, issue 52 point 3).

Usage: python -m lab.campaigns.short_probes [--cache out/cache]

Every cached 1.5 s pinned probe (K 30, default step) of the defaults (stiff legs) and of
`named_params("soft_legs")` is read twice: over 0.5-1.5 s (the longer protocol) and over
0.25-0.75 s (the short one), which is exactly what a 0.75 s run would read (a run's first
0.75 s do not depend on its length). Prints, per regime, how far the drift moved: the median
and 90th percentile, the share beyond the 0.3 mrad floor, and the signs that flipped beyond it.
No simulation: run the soft-leg surface first (`python -m lab.campaigns.soft_legs_surface`) to
fill the cache.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

import numpy as np

from sim_core import default_cache_dir
from sim_core.contract import SHORT_PROBES, SurfaceConfig
from sim_core.research import NAMED_SETTINGS, grid_probes, read_probe

LONG = SurfaceConfig()
FLOOR = LONG.floor_rad


def readings(cache: Path) -> dict[str, list[tuple[float, float | None]]]:
    """(long drift, short drift or None if unusable) of every usable long probe, by regime."""
    regimes = {"stiff (defaults)": {}, "soft legs": dict(NAMED_SETTINGS["soft_legs"])}
    out: dict[str, list[tuple[float, float | None]]] = {name: [] for name in regimes}
    for f in sorted(cache.glob("*.json")):
        stored = json.loads(f.read_text())
        task, result = stored["task"], stored["result"]
        spec, params = json.loads(task["spec"]), json.loads(task["params"])
        plain = spec.get("pin_gain_per_s", LONG.gain_per_s) == LONG.gain_per_s
        if "pin_d31" not in spec or not plain or spec.get("dt_s") or task.get("ramp"):
            continue
        if abs(spec["duration_s"] - (LONG.settle_s + LONG.average_s)) > 1e-9:
            continue
        name = next((n for n, p in regimes.items() if params == p), None)
        if name is None:
            continue
        beta, d = spec.get("beta", 0.66), spec["pin_d31"]
        # the probe as each protocol asks for it (`grid_probes`: beta, D, its averaging)
        short = SHORT_PROBES
        short_cfg = replace(LONG, d31_grid=(d,), settle_s=short.settle_s,
                            average_s=short.average_s, block_s=short.block_s)  # fmt: skip
        long = read_probe(grid_probes([beta], replace(LONG, d31_grid=(d,)))[0], result, LONG)
        if not long.usable or long.drift is None:
            continue
        brief = read_probe(grid_probes([beta], short_cfg)[0], result, short_cfg)
        out[name].append((long.drift, brief.drift if brief.usable else None))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cache", type=Path, default=default_cache_dir())
    args = ap.parse_args()
    for name, rows in readings(args.cache).items():
        pairs = [(a, b) for a, b in rows if b is not None]
        if not pairs:
            print(f"{name}: no cached 1.5 s probes")
            continue
        diff = np.array([abs(b - a) for a, b in pairs]) * 1e3
        flips = sum(abs(a) > FLOOR and abs(b) > FLOOR and (a > 0) != (b > 0) for a, b in pairs)
        print(f"{name}: {len(rows)} probes; drift moved by {np.median(diff):.3f} mrad per cycle "
              f"(median), {np.percentile(diff, 90):.3f} (90%), {np.mean(diff > FLOOR * 1e3):.0%} "
              f"beyond the floor; {flips} signs flipped beyond it; "
              f"{len(rows) - len(pairs)} became unusable")  # fmt: skip


if __name__ == "__main__":
    main()

"""The atlas on short probes against the committed one, cell by cell (issue 54, point 4).

Usage: python -m lab.campaigns.atlas_short_probes --axis mass|slope [--cache DIR] [--workers 2]

Why. Each atlas takes 15 min on 2 cores (882-920 s with its walks, docs/NUMERICS.md); its
surfaces are ~85% of that, probed 0.5 s + 1 s. The short probes (`SHORT_PROBES`, 0.25 s +
0.5 s) move a stiff-leg drift by 0.10 mrad per cycle (median of the 5,574 stiff probes the
atlases ran, `lab.campaigns.short_probes`), and the atlases run the defaults (stiff legs), so
they are the regime where the short probes were validated. Whether they keep every cell's
answer is measured here, not assumed: the atlas of the defaults on short probes (the committed
atlas's betas, values, walks and no last pass) is run from its own cache and each cell's region
compared with the committed `docs/figures/surface_atlas_<axis>_constraint.json` (long probes).

Prints the wall time, simulated seconds, walks, and every cell whose region differs; writes
docs/data/atlas_short_probes_<axis>.json. Run alone on the machine (a study owns the CPU).
The committed data (2026-12-03) compared the atlases as they were before the neighbour walks
(`surface_walks.neighbour_rounds`), which that comparison led to; both sides ran without them.
A rerun today runs both sides with them (the committed atlases and `surface_atlas`'s default).
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

from sim_core import ResultCache, RunStats, WalkConfig, get_backend, surface_atlas
from sim_core.contract import SHORT_PROBES, SurfaceAtlas

ROOT = Path(__file__).resolve().parents[2]  # the checkout
FIGURES = ROOT / "docs" / "figures"
DATA = ROOT / "docs" / "data"


def committed(axis: str) -> SurfaceAtlas:
    """The committed atlas of the defaults on MuJoCo's constraint ground (long probes)."""
    path = FIGURES / f"surface_atlas_{axis}_constraint.json"
    return SurfaceAtlas.model_validate_json(path.read_text())


def compare(before: SurfaceAtlas, after: SurfaceAtlas) -> list[dict[str, object]]:
    """Every cell whose region differs, with both cells' stable states and walks."""
    out: list[dict[str, object]] = []
    for a, b in zip(before.points, after.points, strict=True):
        if (a.beta, a.value) != (b.beta, b.value):
            raise ValueError("the atlases' cells are not in the same order")
        if a.region != b.region or a.undecided != b.undecided:
            out.append({"beta": a.beta, "value": a.value,
                        "before": {"region": a.region, "stable": a.stable,
                                   "walks": len(a.walks), "undecided": a.undecided},
                        "after": {"region": b.region, "stable": b.stable,
                                  "walks": len(b.walks), "undecided": b.undecided}})  # fmt: skip
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--axis", choices=("mass", "slope"), required=True)
    ap.add_argument("--cache", type=Path, default=Path("/work/runs/atlas_short"))
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    before = committed(args.axis)
    cfg = replace(SHORT_PROBES, band_pass=False)
    backend = get_backend("local", args.workers)
    stats = RunStats()
    t0 = time.perf_counter()
    try:
        after = surface_atlas(
            args.axis, before.betas, before.values, cache=ResultCache(args.cache / args.axis),
            backend=backend, config=cfg, walks=WalkConfig(), stats=stats,
        )  # fmt: skip
    finally:
        backend.close()
    wall = time.perf_counter() - t0
    diffs = compare(before, after)
    walks = [w for p in after.points for w in p.walks]
    report = {
        "axis": args.axis, "wall_s": round(wall, 1), "workers": args.workers,
        "sim_s": after.sim_s, "sim_s_before": before.sim_s,
        "computed": stats.computed, "cached": stats.cached,
        "compute_s": round(stats.compute_s, 1),
        "walks": len(walks), "walks_sim_s": sum(w.sim_s for w in walks),
        "walks_before": sum(len(p.walks) for p in before.points),
        "cells": len(after.points), "cells_differ": len(diffs), "differences": diffs,
        "undecided": sum(p.undecided for p in after.points),
        "atlas": json.loads(after.model_dump_json()),
    }  # fmt: skip
    DATA.mkdir(parents=True, exist_ok=True)
    (DATA / f"atlas_short_probes_{args.axis}.json").write_text(json.dumps(report, indent=1))
    print(f"{args.axis}: {wall:.0f} s wall on {args.workers} workers; {after.sim_s:.0f} simulated "
          f"s (committed: {before.sim_s:.0f}); {stats.computed} computed, {stats.cached} cached; "
          f"{len(walks)} walks ({report['walks_sim_s']:.0f} s; committed "
          f"{report['walks_before']}); {len(diffs)} of {len(after.points)} cells differ; "
          f"{report['undecided']} undecided")  # fmt: skip
    for d in diffs:
        print(f"  beta {d['beta']:g}, {args.axis} {d['value']:g}: {d['before']} -> {d['after']}")


if __name__ == "__main__":
    main()

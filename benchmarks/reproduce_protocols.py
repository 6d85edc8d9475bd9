"""`insect-gait reproduce` on two protocols side by side in one run, each from an empty cache:
an earlier protocol (`--before dense`, the default: `ReproduceConfig.dense_protocol()`, the
protocol of 2026-12-02, 552-600 s on 2 cores; `--before long`: the one before issue 54,
`ReproduceConfig.long_protocol()`) and today's default. Prints each one's wall time,
simulations and compute, their ratio, and every row of the reproduction table beside the
other's, marking the rows whose verdict or number moved (docs/NUMERICS.md, "reproduce within
5 minutes").

    .venv/bin/python benchmarks/reproduce_protocols.py [--before dense|long] [--workers 2]
        [--json out.json]

Both runs use fresh temporary caches and output folders and touch no file of the repository
(no --doc); a run on a loaded machine measures the load, so run it alone.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path
from typing import Any

from sim_core import get_backend
from sim_core.paper.reproduce import reproduce
from sim_core.research import ReproduceConfig


def table_rows(table: str) -> dict[str, tuple[str, str]]:
    """The reproduction table's rows by what the paper states: (ours, reproduced?)."""
    rows: dict[str, tuple[str, str]] = {}
    for line in table.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 4 and cells[0] not in ("paper states", "---"):
            rows[cells[0]] = (cells[2], cells[3])
    return rows


def run(cfg: ReproduceConfig, workers: int, root: Path) -> dict[str, Any]:
    """One reproduce of every figure on `cfg`, from an empty cache under `root`."""
    backend = get_backend("local", workers)
    t0 = time.perf_counter()
    try:
        report = reproduce(["all"], cfg, root / f"out-{cfg.name}", root / f"cache-{cfg.name}",
                           backend, doc=None, progress=False)  # fmt: skip
    finally:
        backend.close()
    return {
        "protocol": cfg.name,
        "wall_s": round(time.perf_counter() - t0, 1),
        "simulations": report.stats.computed,
        "compute_s": round(report.stats.compute_s, 1),
        "rows": table_rows(report.table),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", choices=("dense", "long"), default="dense")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--json", type=Path, help="also write the measurement here")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="reproduce-protocols-") as tmp:
        before = {"dense": ReproduceConfig.dense_protocol, "long": ReproduceConfig.long_protocol}
        runs = [run(c, args.workers, Path(tmp)) for c in
                (before[args.before](), ReproduceConfig())]  # fmt: skip
    old, new = runs
    for r in runs:
        print(f"{r['protocol']:>5}: {r['wall_s']:7.1f} s wall, {r['simulations']} simulations, "
              f"{r['compute_s']:.0f} s of single-core compute")  # fmt: skip
    print(f"ratio {new['wall_s'] / old['wall_s']:.2f} (wall), "
          f"{new['compute_s'] / old['compute_s']:.2f} (compute)\n")  # fmt: skip
    moved = 0
    for key, (ours_old, verdict_old) in old["rows"].items():
        ours_new, verdict_new = new["rows"].get(key, ("(missing)", "(missing)"))
        same = ours_new == ours_old and verdict_new == verdict_old
        moved += not same
        mark = "  " if same else ("V " if verdict_new != verdict_old else "* ")
        print(f"{mark}{key}\n     {old['protocol']}: {ours_old} [{verdict_old}]")
        if not same:
            print(f"     now:  {ours_new} [{verdict_new}]")
    print(f"\n{moved} of {len(old['rows'])} rows moved (V: the verdict, *: the number only)")
    if args.json:
        args.json.write_text(json.dumps({"runs": runs, "workers": args.workers}, indent=1))


if __name__ == "__main__":
    main()

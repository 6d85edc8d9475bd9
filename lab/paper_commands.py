"""The lab's paper commands: the finder's atlas, check and claims, and the old `study` (the
product's `insect-gait` keeps reproduce and finder, sim_core/cli/paper.py; `study` runs its
`reproduce` through `sim_core.cli.main`). The checks themselves are lab/finder_check.py and
lab/finder_claims.py."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sim_core import default_cache_dir
from sim_core.cli import EXIT_USAGE, add_backend_args, backend_from_args
from sim_core.contract import BIFURCATION_FILE, RESULTS_DIR

if TYPE_CHECKING:
    from sim_core.contract import AtlasOutput


def _add_study(sub: Any) -> None:
    p = sub.add_parser(
        "study", help="old name of `reproduce --figure 5 7` followed by `sensitivity`"
    )
    p.add_argument("--out", default=None, help="folder (default as for reproduce)")
    p.add_argument("--quick", action="store_true", help="tiny sizes; no sensitivity")
    p.add_argument("--no-sensitivity", action="store_true")
    p.set_defaults(func=_cmd_study)


def _cmd_study(args: argparse.Namespace) -> int:
    from lab.sensitivity import run_sensitivity
    from sim_core.cli import main as insect_gait

    # `insect-gait reproduce --figure 5 7 --no-doc` (default cache and local backend)
    argv = ["reproduce", "--figure", "5", "7", "--no-doc"]
    if args.out is not None:
        argv.append(f"--out={args.out}")
    if args.quick:
        argv.append("--quick")
    rc = insect_gait(argv)
    if rc != 0 or args.quick or args.no_sensitivity:
        return rc
    run_sensitivity(Path(args.out or RESULTS_DIR))
    return 0


def _add_atlas(sub: Any) -> None:
    from sim_core.research import BACKENDS

    p = sub.add_parser(
        "finder-atlas",
        help="the finder's gait atlas: stable gaits over beta x body mass or beta x slope from "
        "settled free runs (the independent check of `atlas`)",
    )
    p.add_argument("--axis", choices=["mass", "slope"], required=True,
                   help="the second axis: body mass (g) or slope (deg)")  # fmt: skip
    p.add_argument("--quick", action="store_true",
                   help="a 2 x 2 grid of short runs: the machinery, not science")  # fmt: skip
    p.add_argument("--out", default=None,
                   help=f"folder for atlas_<axis>.json/png (default {RESULTS_DIR}; --quick: "
                   "out/atlas-quick)")  # fmt: skip
    add_backend_args(p, [b for b in BACKENDS if b != "ray"])
    p.add_argument("--no-progress", action="store_true", help="no progress output")
    p.set_defaults(func=_cmd_atlas)


def _cmd_atlas(args: argparse.Namespace) -> int:
    import time

    from sim_core import ResultCache, RunStats
    from sim_core.research import AtlasConfig, run_atlas, write_atlas

    prog = "python -m lab finder-atlas"
    cfg = AtlasConfig.quick(args.axis) if args.quick else AtlasConfig(args.axis)
    out = Path(args.out or ("out/atlas-quick" if args.quick else RESULTS_DIR))
    backend = backend_from_args(args, prog)
    if backend is None:
        return EXIT_USAGE
    stats = RunStats()
    t0 = time.perf_counter()
    try:
        atlas = run_atlas(cfg, ResultCache(args.cache), backend, progress=not args.no_progress,
                          stats=stats)  # fmt: skip
    except KeyboardInterrupt:
        print(f"{prog}: interrupted; finished simulations are cached in {args.cache}: run the "
              "same command again to resume", file=sys.stderr)  # fmt: skip
        return 130
    finally:
        backend.close()
    files = write_atlas(atlas, out)
    wall = time.perf_counter() - t0
    print("\n".join(_atlas_summary(atlas)))
    sim_s = sum(c.sim_s for c in atlas.cells)
    print(
        f"\nwall time {wall:.1f} s on {backend.name} with {backend.workers} worker(s); "
        f"{stats.computed} simulations computed, {stats.cached} cached; {sim_s:.0f} "
        f"simulated s ({sim_s / wall:.2f} per wall s); wrote {', '.join(map(str, files))}"
    )
    return 0


def _atlas_summary(out: AtlasOutput) -> list[str]:
    """One line per value row: the region at each beta."""
    from sim_core.contract import AXIS_PARAM

    lines = [f"{AXIS_PARAM[out.axis]:>12} | " + " | ".join(f"β {b:g}" for b in out.betas)]
    for v, regs in zip(out.values, out.regions, strict=True):
        lines.append(f"{v:>12g} | " + " | ".join(regs))
    return lines


def _add_finder_check(sub: Any) -> None:
    p = sub.add_parser(
        "finder-check",
        help="check the fixed-point finder against independent 40 s runs",
    )
    p.add_argument("--beta", type=float, nargs="+", default=[0.62, 0.655, 0.70],
                   help="betas to check (default %(default)s)")  # fmt: skip
    p.add_argument("--grid", choices=("fig8", "alone"), default="fig8",
                   help="the finder runs over Fig. 8's beta grid (as reproduce, whose runs the "
                        "cache then holds) or over the checked betas alone (default "
                        "%(default)s)")  # fmt: skip
    p.add_argument("--cache", default=str(default_cache_dir()),
                   help="task result cache folder (resumes; default: the installation's, shared "
                   "with the CLI and the API)")  # fmt: skip
    p.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_finder_check)


def _cmd_finder_check(args: argparse.Namespace) -> int:
    import time

    from lab.finder_check import report, validate
    from sim_core import ResultCache, RunStats, get_backend
    from sim_core.research import ReproduceConfig

    for b in args.beta:
        if not 0.5 < b < 1.0:
            print(f"python -m lab finder-check: error: --beta {b:g} is outside (0.5, 1)",
                  file=sys.stderr)  # fmt: skip
            return EXIT_USAGE
    backend = get_backend("local", args.workers)
    stats = RunStats()
    t0 = time.perf_counter()
    try:
        cfg = ReproduceConfig()
        grid = cfg.bif_betas if args.grid == "fig8" else None
        checks = validate(args.beta, cfg.finder, ResultCache(args.cache), backend, grid=grid,
                          progress=not args.no_progress, stats=stats)  # fmt: skip
    finally:
        backend.close()
    print("\n".join(report(checks)))
    print(f"\nwall time {time.perf_counter() - t0:.1f} s; {stats.computed} simulations "
          f"computed, {stats.cached} cached")  # fmt: skip
    return 0 if all(c.ok for c in checks) else 1


def _add_finder_claims(sub: Any) -> None:
    p = sub.add_parser(
        "finder-claims",
        help="the finder's stable points at dt/2, their landing share, and the tripod's fold "
        "under +-10%% of each calibrated parameter",
    )
    p.add_argument("--what", choices=("numerics", "robustness", "all"), default="all",
                   help="numerics: dt/2 and landing share of the stable points; robustness: "
                        "+-10%% of each calibrated parameter (default %(default)s)")  # fmt: skip
    p.add_argument("--beta", type=float, nargs="+", default=[0.62, 0.645, 0.655, 0.70],
                   help="betas whose stable points get the numerics check (default "
                        "%(default)s)")  # fmt: skip
    p.add_argument("--bifurcation", type=Path, default=RESULTS_DIR / BIFURCATION_FILE,
                   help="the finder's output to check (reproduce writes it; default "
                        "%(default)s)")  # fmt: skip
    p.add_argument(
        "--out",
        type=Path,
        default=Path("out/claims"),
        help="folder for claims.json and claims.md (default %(default)s)",
    )
    p.add_argument("--threads", type=int, default=0, help="simulation threads (0: all cores)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_finder_claims)


def _cmd_finder_claims(args: argparse.Namespace) -> int:
    import json
    import time
    from dataclasses import asdict

    from tqdm import tqdm

    from lab.finder_claims import numerics, numerics_report, robustness, robustness_report
    from sim_core.contract import FinderOutput
    from sim_core.research import branch_ranges

    try:
        found = FinderOutput.model_validate_json(args.bifurcation.read_text())
    except (OSError, ValueError) as e:
        print(f"python -m lab finder-claims: error: cannot read the finder's output "
              f"{args.bifurcation}: {e}", file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    args.out.mkdir(parents=True, exist_ok=True)
    lines: list[str] = []
    record: dict[str, Any] = {"bifurcation": str(args.bifurcation)}
    for what in ("numerics", "robustness"):
        if args.what not in (what, "all"):
            continue
        t0 = time.perf_counter()
        with tqdm(total=1.0, desc=what, disable=args.no_progress,
                  bar_format="{l_bar}{bar}| {elapsed}<{remaining}") as bar:  # fmt: skip

            def progress(f: float, bar: Any = bar) -> None:
                bar.n = round(f, 3)
                bar.refresh()

            if what == "numerics":
                folds = [f["beta"] for g in ("tripod", "metachronal")
                         for f in branch_ranges(found.cells, g)["folds"]]  # fmt: skip
                checks = numerics(found, args.beta, folds, nthread=args.threads,
                                  progress=progress)  # fmt: skip
                rows = numerics_report(checks)
                record[what] = [asdict(c) | {"same": c.same, "lands_ok": c.lands_ok}
                                for c in checks]  # fmt: skip
            else:
                variants = robustness(nthread=args.threads, progress=progress)
                rows = robustness_report(variants)
                record[what] = [asdict(v) | {"fold": v.fold()} for v in variants]
        wall = time.perf_counter() - t0
        record[f"{what}_wall_s"] = wall
        lines += [f"{what} ({wall:.0f} s wall):", "", *rows, ""]
    (args.out / "claims.json").write_text(json.dumps(record, indent=1))
    (args.out / "claims.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


def register(sub: Any) -> None:
    """The finder's studies and checks (`python -m lab`)."""
    _add_atlas(sub)
    _add_finder_check(sub)
    _add_finder_claims(sub)
    _add_study(sub)

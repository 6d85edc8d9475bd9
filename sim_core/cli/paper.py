"""`reproduce` (the paper's Figs. 5-9), the fixed-point finder (`finder`, `finder-check`,
`finder-claims`), the finder's atlas (`finder-atlas`), and `study` (the old name of reproduce)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sim_core.cli.common import EXIT_USAGE, doc_to_update
from sim_core.paper.results import BIFURCATION_FILE, RESULTS_DIR, RESULTS_ENV


def _add_backend_args(p: Any, backends: Sequence[str]) -> None:
    """Where the runs go and where they are kept: shared by `reproduce` and `atlas`."""
    p.add_argument("--cache", default="out/cache", help="task result cache folder (resumes)")
    p.add_argument("--backend", choices=list(backends), default="local",
                   help="local: process pool on this machine; dask: dask.distributed")  # fmt: skip
    p.add_argument("--address", default=None, help="dask scheduler, e.g. tcp://host:8786")
    p.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")


def backend_from_args(args: argparse.Namespace, prog: str) -> Any:
    """The backend `_add_backend_args`' options name, or None after printing why not (a bad
    --workers, or a backend that cannot run here) in one line."""
    from sim_core.runs.backends import BackendUnavailable, get_backend

    if args.workers is not None and args.workers < 1:
        print(f"{prog}: error: --workers must be >= 1", file=sys.stderr)
        return None
    try:
        return get_backend(args.backend, args.workers, args.address)
    except BackendUnavailable as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return None


def _add_reproduce(sub: Any) -> None:
    from sim_core.paper.values import FIGURES
    from sim_core.runs import BACKENDS

    p = sub.add_parser(
        "reproduce", help="the paper's Figs. 5-9 + ablation: figures, data, reproduction table"
    )
    p.add_argument("--figure", nargs="+", choices=[*FIGURES, "all"], default=["all"],
                   help="which figures (default all)")  # fmt: skip
    p.add_argument(
        "--out",
        default=None,
        help=f"folder (default {RESULTS_DIR}, ${RESULTS_ENV} overrides; "
        f"--quick: out/reproduce-quick)",
    )
    _add_backend_args(p, BACKENDS)
    p.add_argument("--quick", action="store_true", help="tiny sizes: a smoke test, not science")
    p.add_argument("--doc", default=None,
                   help="markdown file whose reproduce section to regenerate (default "
                   "docs/REPRODUCTION.md; none with --quick)")  # fmt: skip
    p.add_argument("--no-doc", action="store_true", help="do not touch any markdown file")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_reproduce)


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from sim_core.paper.figures import Config
    from sim_core.paper.reproduce import reproduce

    prog = "insect-gait reproduce"
    cfg = Config.quick() if args.quick else Config()
    out = Path(args.out or ("out/reproduce-quick" if args.quick else RESULTS_DIR))
    try:
        doc = doc_to_update(args, "docs/REPRODUCTION.md")
    except FileNotFoundError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    backend = backend_from_args(args, prog)
    if backend is None:
        return EXIT_USAGE
    try:
        report = reproduce(args.figure, cfg, out, Path(args.cache), backend, doc=doc,
                           progress=not args.no_progress)  # fmt: skip
    except KeyboardInterrupt:
        print(f"{prog}: interrupted; finished simulations are cached in {args.cache}: "
              "run the same command again to resume", file=sys.stderr)  # fmt: skip
        return 130
    finally:
        backend.close()
    print(report.table)
    s = report.stats
    print(f"\nwall time {report.wall_s:.1f} s; {s.computed} of {s.tasks} simulations computed, "
          f"{s.cached} cached; wrote {len(report.files)} files to {out}"
          + (f" and the table in {doc}" if doc else ""))  # fmt: skip
    return 0


def _add_study(sub: Any) -> None:
    p = sub.add_parser(
        "study", help="old name of `reproduce --figure 5 7` followed by `sensitivity`"
    )
    p.add_argument("--out", default=None, help="folder (default as for reproduce)")
    p.add_argument("--quick", action="store_true", help="tiny sizes; no sensitivity")
    p.add_argument("--no-sensitivity", action="store_true")
    p.set_defaults(func=_cmd_study)


def _cmd_study(args: argparse.Namespace) -> int:
    from sim_core.studies.sensitivity import run_sensitivity

    rc = _cmd_reproduce(argparse.Namespace(
        figure=["5", "7"], out=args.out, cache="out/cache", backend="local", address=None,
        workers=None, quick=args.quick, doc=None, no_doc=True, no_progress=False,
    ))  # fmt: skip
    if rc != 0 or args.quick or args.no_sensitivity:
        return rc
    run_sensitivity(Path(args.out or RESULTS_DIR))
    return 0


def _add_atlas(sub: Any) -> None:
    from sim_core.runs import BACKENDS

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
    _add_backend_args(p, [b for b in BACKENDS if b != "ray"])
    p.add_argument("--no-progress", action="store_true", help="no progress output")
    p.set_defaults(func=_cmd_atlas)


def _cmd_atlas(args: argparse.Namespace) -> int:
    import time

    from sim_core.paper.atlas import AtlasConfig, run_atlas, summary_lines, write_atlas
    from sim_core.runs.backends import RunStats
    from sim_core.runs.cache import ResultCache

    prog = "insect-gait-lab finder-atlas"
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
    print("\n".join(summary_lines(atlas)))
    sim_s = sum(c.sim_s for c in atlas.cells)
    print(
        f"\nwall time {wall:.1f} s on {backend.name} with {backend.workers} worker(s); "
        f"{stats.computed} simulations computed, {stats.cached} cached; {sim_s:.0f} "
        f"simulated s ({sim_s / wall:.2f} per wall s); wrote {', '.join(map(str, files))}"
    )
    return 0


def _add_finder(sub: Any) -> None:
    from sim_core.runs import BACKENDS

    p = sub.add_parser(
        "finder",
        help="the settled fixed-point finder over Fig. 8's betas (the drift surface's "
        "independent check): writes bifurcation.json for surface-check and the viewer",
    )
    p.add_argument("--beta", type=float, nargs="+", default=None,
                   help="betas (default: Fig. 8's grid, 0.62-0.70 by 0.005)")  # fmt: skip
    p.add_argument("--out", type=Path, default=RESULTS_DIR,
                   help=f"folder for {BIFURCATION_FILE} (default %(default)s)")  # fmt: skip
    _add_backend_args(p, BACKENDS)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_finder)


def _cmd_finder(args: argparse.Namespace) -> int:
    import time
    from dataclasses import asdict

    from sim_core.paper.figures import Config
    from sim_core.paper.fixedpoints import Cell, FinderOutput, find
    from sim_core.paper.search import task_runner
    from sim_core.runs.backends import RunStats
    from sim_core.runs.cache import ResultCache

    prog = "insect-gait finder"
    cfg = Config()
    betas = sorted(set(args.beta or cfg.bif_betas))
    bad = [b for b in betas if not 0.5 < b < 1.0]
    if bad:
        print(f"{prog}: error: --beta {bad[0]:g} is outside (0.5, 1)", file=sys.stderr)
        return EXIT_USAGE
    backend = backend_from_args(args, prog)
    if backend is None:
        return EXIT_USAGE
    stats = RunStats()
    t0 = time.perf_counter()
    try:
        run = task_runner(ResultCache(args.cache), backend, None, chunk_size=cfg.chunk_size,
                          progress=not args.no_progress, stats=stats)  # fmt: skip
        cells = find([Cell(b) for b in betas], cfg.finder, run)
    finally:
        backend.close()
    out = FinderOutput(source="insect-gait finder: the settled fixed-point finder",
                       config=asdict(cfg.finder), cells=cells)  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / BIFURCATION_FILE).write_text(out.model_dump_json())
    for c in cells:
        states = ", ".join(f"{a.d31:.3f} ({a.gait})" for a in c.stable()) or "none confirmed"
        borders = ", ".join(f"{b.d31:.3f}" for b in c.borders if b.d31 is not None)
        print(f"beta {c.beta:g}: stable {states}" + (f"; borders {borders}" if borders else ""))
    wall = time.perf_counter() - t0
    print(f"{stats.computed} runs computed, {stats.cached} cached, in {wall:.0f} s wall; "
          f"wrote {args.out / BIFURCATION_FILE}")  # fmt: skip
    return 0


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
    p.add_argument("--cache", default="out/cache", help="task result cache folder (resumes)")
    p.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_finder_check)


def _cmd_finder_check(args: argparse.Namespace) -> int:
    import time

    from sim_core.paper.figures import Config
    from sim_core.paper.validation import report, validate
    from sim_core.runs.backends import RunStats, get_backend
    from sim_core.runs.cache import ResultCache

    for b in args.beta:
        if not 0.5 < b < 1.0:
            print(f"insect-gait-lab finder-check: error: --beta {b:g} is outside (0.5, 1)",
                  file=sys.stderr)  # fmt: skip
            return EXIT_USAGE
    backend = get_backend("local", args.workers)
    stats = RunStats()
    t0 = time.perf_counter()
    try:
        cfg = Config()
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

    from sim_core.paper.claims import numerics, numerics_report, robustness, robustness_report
    from sim_core.paper.fixedpoints import FinderOutput, branch_ranges

    try:
        found = FinderOutput.model_validate_json(args.bifurcation.read_text())
    except (OSError, ValueError) as e:
        print(f"insect-gait-lab finder-claims: error: cannot read the finder's output "
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
    """The product's paper commands."""
    _add_reproduce(sub)
    _add_finder(sub)


def register_lab(sub: Any) -> None:
    """The finder's studies and checks (`insect-gait-lab`)."""
    _add_atlas(sub)
    _add_finder_check(sub)
    _add_finder_claims(sub)
    _add_study(sub)

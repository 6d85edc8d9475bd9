"""`reproduce` (the paper's Figs. 5-9) and the fixed-point finder (`finder`); the finder's
checks and atlas are the lab's (`python -m lab`, lab/paper_commands.py), which words its
backend options with `add_backend_args` and `backend_from_args` (public: `sim_core.cli`)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sim_core.cli.common import EXIT_USAGE, UsageError, doc_to_update, out_folder
from sim_core.cli.model import add_model_args, choice_from_args, model_line
from sim_core.cli.runflags import (
    add_run_flags,
    check_runs,
    output_tag,
    provenance_fields,
    run_fields,
    split_condition,
    tagged,
)
from sim_core.contract.results import BIFURCATION_FILE, RESULTS_DIR, RESULTS_ENV
from sim_core.runs import CACHE_DIR_ENV, default_cache_dir, default_cache_max_bytes


def add_backend_args(p: Any, backends: Sequence[str]) -> None:
    """Where the runs go and where they are kept: shared by `reproduce`, `finder`, `atlas` and
    the lab's commands."""
    p.add_argument("--cache", default=str(default_cache_dir()),
                   help="folder that keeps every finished simulation, so that the same command "
                   "run again resumes and reads them back; shared with the REST service's jobs "
                   f"(default %(default)s: ${CACHE_DIR_ENV}, else the installation's; "
                   "`insect-gait cache info`)")  # fmt: skip
    p.add_argument("--backend", choices=list(backends), default="local",
                   help="local: process pool on this machine; dask: dask.distributed")  # fmt: skip
    p.add_argument("--address", default=None, help="dask scheduler, e.g. tcp://host:8786")
    p.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")


def backend_from_args(args: argparse.Namespace, prog: str) -> Any:
    """The backend `add_backend_args`' options name, or None after printing why not (a bad
    --workers, a --cache that cannot be made, or a backend that cannot run here) in one line.
    The last check before a command computes: with progress on, it says once, on stderr,
    where the runs are cached (a rerun reads them back)."""
    from sim_core.runs.backends import BackendUnavailable, get_backend

    if args.workers is not None and args.workers < 1:
        print(f"{prog}: error: --workers must be >= 1", file=sys.stderr)
        return None
    try:
        Path(args.cache).mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        print(f"{prog}: error: --cache {args.cache}: {exc.strerror or exc}", file=sys.stderr)
        return None
    try:
        backend = get_backend(args.backend, args.workers, args.address)
    except BackendUnavailable as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return None
    if not getattr(args, "no_progress", False):
        print(f"{prog}: finished runs are cached in {args.cache} (--cache): the same command "
              "again reads them back", file=sys.stderr)  # fmt: skip
    return backend


def cache_from_args(args: argparse.Namespace) -> Any:
    """The `ResultCache` at --cache, with the installation's size limit
    ($INSECT_GAIT_CACHE_MAX_BYTES): a command's new results push the least recently used out."""
    from sim_core.runs.cache import ResultCache

    try:
        limit = default_cache_max_bytes()
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    return ResultCache(args.cache, max_bytes=limit)


def _add_reproduce(sub: Any) -> None:
    from sim_core.contract.values import FIGURES
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
    add_backend_args(p, BACKENDS)
    p.add_argument("--quick", action="store_true", help="tiny sizes: a smoke test, not science")
    p.add_argument("--doc", default=None,
                   help="markdown file whose reproduce section to regenerate (default "
                   "docs/REPRODUCTION.md; none with --quick)")  # fmt: skip
    p.add_argument("--no-doc", action="store_true", help="do not touch any markdown file")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_reproduce)


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from sim_core.paper.figures import ReproduceConfig
    from sim_core.paper.reproduce import reproduce

    prog = "insect-gait reproduce"
    cfg = ReproduceConfig.quick() if args.quick else ReproduceConfig()
    doc = doc_to_update(args, "docs/REPRODUCTION.md", "reproduce")
    out = out_folder(args.out or ("out/reproduce-quick" if args.quick else RESULTS_DIR), "--out")
    backend = backend_from_args(args, prog)
    if backend is None:
        return EXIT_USAGE
    cache = cache_from_args(args)
    try:
        report = reproduce(args.figure, cfg, out, Path(args.cache), backend, doc=doc,
                           progress=not args.no_progress)  # fmt: skip
    except KeyboardInterrupt:
        print(f"{prog}: interrupted; finished simulations are cached in {args.cache}: "
              "run the same command again to resume", file=sys.stderr)  # fmt: skip
        return 130
    finally:
        backend.close()
    cache.trim()  # reproduce keeps its own cache object; the limit holds once it is done
    print(report.table)
    s = report.stats
    print(f"\nwall time {report.wall_s:.1f} s; {s.computed} of {s.tasks} simulations computed, "
          f"{s.cached} cached; wrote {len(report.files)} files to {out}"
          + (f" and the table in {doc}" if doc else ""))  # fmt: skip
    return 0


# what the finder sets per run itself: beta (--beta, a cell each), the starts, each run's
# length and its settled try (FinderConfig); every other RunSpec field is a flag and reaches
# every run (body mass and slope through the cells)
FINDER_VARIES = ("beta", "d31_init", "duration_s", "stop_if_settled_s")


def _add_finder(sub: Any) -> None:
    from sim_core.runs import BACKENDS

    p = sub.add_parser(
        "finder",
        help="the settled fixed-point finder over Fig. 8's betas (the drift surface's "
        "independent check): writes bifurcation.json for surface-check and the viewer",
        description="The settled fixed-point finder at each beta: runs from starts spread "
        "over the circle, judged by the settled rule, with the basin borders between the "
        "states found. The runs' other options are the run's (RunSpec), as `run` takes "
        "them; with other options or model parameters than the defaults, the file's name "
        "gains a tag (bifurcation-TAG.json) and its config records them.",
    )
    p.add_argument("--beta", type=float, nargs="+", default=None,
                   help="betas (default: Fig. 8's grid, 0.62-0.70 by 0.005)")  # fmt: skip
    add_run_flags(p, vary=FINDER_VARIES)
    add_model_args(p)
    p.add_argument("--out", type=Path, default=RESULTS_DIR,
                   help=f"folder for {BIFURCATION_FILE} (default %(default)s)")  # fmt: skip
    add_backend_args(p, BACKENDS)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_finder)


def _finder_fields(args: argparse.Namespace, betas: list[float]) -> dict[str, Any]:
    """The run fields given, checked for every beta's runs by RunSpec's rules and the
    numerics' (a UsageError naming the flag otherwise)."""
    from sim_core.model.spec import numerics_problem

    fields = run_fields(args)
    for b in betas:
        check_runs(fields | {"beta": b})
    problem = numerics_problem(fields.get("integrator"), fields.get("dt_s"),
                               fields.get("control_dt_s"))  # fmt: skip
    if problem:
        raise UsageError(f"--dt-s: {problem}")
    return fields


def _cmd_finder(args: argparse.Namespace) -> int:
    import time

    from sim_core.contract.finder import Cell, FinderOutput
    from sim_core.contract.template import RunTemplate
    from sim_core.paper.figures import ReproduceConfig
    from sim_core.paper.finder import find
    from sim_core.paper.search import task_runner
    from sim_core.runs.backends import RunStats

    prog = "insect-gait finder"
    cfg = ReproduceConfig()
    betas = sorted(set(args.beta or cfg.bif_betas))
    bad = [b for b in betas if not 0.5 < b < 1.0]
    if bad:
        print(f"{prog}: error: --beta {bad[0]:g} is outside (0.5, 1)", file=sys.stderr)
        return EXIT_USAGE
    choice = choice_from_args(args)
    fields = _finder_fields(args, betas)
    at, shared = split_condition(fields)  # the cells' condition; every run's fields
    folder = out_folder(args.out, "--out")
    path = tagged(folder / BIFURCATION_FILE, output_tag(fields, choice))
    backend = backend_from_args(args, prog)
    if backend is None:
        return EXIT_USAGE
    stats = RunStats()
    t0 = time.perf_counter()
    try:
        bar = False if args.no_progress else "finder"
        run = task_runner(cache_from_args(args), backend, choice.model_params(),
                          chunk_size=cfg.chunk_size, progress=bar, stats=stats,
                          template=RunTemplate.model_validate(shared))  # fmt: skip
        cells = find([Cell(b, **at) for b in betas], cfg.finder, run)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted; finished runs are cached in {args.cache}: run the same "
              "command again to resume", file=sys.stderr)  # fmt: skip
        return 130
    finally:
        backend.close()
    out = FinderOutput(source="insect-gait finder: the settled fixed-point finder",
                       config=cfg.finder, cells=cells,
                       **provenance_fields(fields, choice))  # fmt: skip
    path.write_text(out.model_dump_json())
    for c in cells:
        states = ", ".join(f"{a.d31:.3f} ({a.gait})" for a in c.stable()) or "none confirmed"
        borders = ", ".join(f"{b.d31:.3f}" for b in c.borders if b.d31 is not None)
        print(f"beta {c.beta:g}: stable {states}" + (f"; borders {borders}" if borders else ""))
    wall = time.perf_counter() - t0
    print(f"{stats.computed} runs computed, {stats.cached} cached, in {wall:.0f} s wall; "
          f"wrote {path}")  # fmt: skip
    if model_line(choice):
        print(model_line(choice))
    return 0


def register(sub: Any) -> None:
    """The product's paper commands."""
    _add_reproduce(sub)
    _add_finder(sub)

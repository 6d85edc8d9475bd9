"""`bench`, `converge` and `numerics`: what the numerics cost and how far to trust them."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

from sim_core.cli.common import UsageError, doc_to_update, one_line, out_folder
from sim_core.cli.model import add_model_args, choice_from_args, model_line
from sim_core.cli.runflags import add_run_flags, check_runs, run_fields
from sim_core.contract.results import RESULTS_DIR, RESULTS_ENV
from sim_core.model.params import ModelParams

# what `converge` sets per run itself (`convergence_check`: its betas and starts)
CONVERGE_VARIES = ("beta", "d31_init")


def _runs_valid(flags: dict[str, str] | None = None, **fields: Any) -> None:
    """The runs a command will make, checked by RunSpec's rules before anything runs: a
    UsageError in RunSpec's words, each field named by its flag (as `run` words them; `flags`
    names those the command calls otherwise)."""
    check_runs({"beta": 0.62} | fields, flags)


def _add_bench(sub: Any) -> None:
    p = sub.add_parser("bench", help="speed of one and many simulations, side by side")
    p.add_argument("--json", action="store_true")
    p.add_argument("--sim-seconds", type=float, default=2.0, help="simulated s per measurement")
    p.add_argument("--nsim", type=int, default=32, help="batch size")
    p.set_defaults(func=_cmd_bench)


def _cmd_bench(args: argparse.Namespace) -> int:
    from sim_core.numerics.bench import run_bench

    if args.nsim < 1:
        raise UsageError(f"--nsim: must be >= 1 (simulations in the batch), got {args.nsim}")
    _runs_valid({"duration_s": "--sim-seconds"}, duration_s=args.sim_seconds)
    report = run_bench(sim_seconds=args.sim_seconds, nsim=args.nsim, verbose=not args.json)
    if args.json:
        print(json.dumps(report))
    return 0


# converge's runs: long enough for most starts to settle at the default step (docs/NUMERICS.md)
CONVERGE_DURATION_S = 6.0


def _add_converge(sub: Any) -> None:
    p = sub.add_parser(
        "converge",
        help="same gait outcomes at dt and dt/2? (default numerics)",
        description="The gait outcomes (final Delta31, gait) of starts spread over the circle "
        "at three betas, run at --dt-s and at half of it. The runs' other options are the "
        "run's (RunSpec), as `run` takes them.",
    )
    add_run_flags(p, vary=CONVERGE_VARIES, defaults={
        "duration_s": f"{CONVERGE_DURATION_S:g}",
        "dt_s": f"the model's, {ModelParams().numerics.dt:g}; the check also runs at half of it",
    })  # fmt: skip
    add_model_args(p)
    p.add_argument("--tolerance", type=float, default=0.05,
                   help="largest final Delta31 difference that agrees, rad (> 0)")  # fmt: skip
    p.set_defaults(func=_cmd_converge)


def _cmd_converge(args: argparse.Namespace) -> int:
    from sim_core.numerics.convergence import convergence_check

    if not (math.isfinite(args.tolerance) and args.tolerance > 0):
        raise UsageError(f"--tolerance: must be a finite number > 0 (rad), got {args.tolerance}")
    choice = choice_from_args(args)
    fields = {"duration_s": CONVERGE_DURATION_S} | run_fields(args)
    _runs_valid(**fields)
    report = convergence_check(choice.model_params(), **fields)
    print(report.summary(args.tolerance))
    if model_line(choice):
        print(model_line(choice))
    return 0 if all(report.agree(args.tolerance)) else 1


def _add_numerics(sub: Any) -> None:
    p = sub.add_parser("numerics", help="integrator x timestep grid against RK4 at 2e-5 s")
    p.add_argument("--quick", action="store_true", help="a coarse grid, short runs")
    p.add_argument(
        "--out",
        default=None,
        help=f"folder (default {RESULTS_DIR}, ${RESULTS_ENV} overrides; "
        f"--quick: out/numerics-quick)",
    )
    p.add_argument("--doc", default=None,
                   help="markdown file whose numerics section to regenerate (default "
                   "docs/NUMERICS.md; none with --quick)")  # fmt: skip
    p.add_argument("--no-doc", action="store_true", help="do not touch any markdown file")
    p.add_argument("--from-json", default=None, metavar="PATH",
                   help="redraw figures and table from a numerics.json; no simulation")  # fmt: skip
    p.add_argument("--solver-options", action="store_true",
                   help="instead of the grid: MuJoCo's solver options (iterations, solver, "
                   "cone, warm start, tolerance) and the controller period at the default "
                   "timestep, each one's speed and outcome error side by side")  # fmt: skip
    p.set_defaults(func=_cmd_numerics)


def _cmd_solver_options() -> int:
    from sim_core.numerics.solver import options_markdown, solver_options_study

    rows, _ = solver_options_study(progress=print)
    print()
    print(options_markdown(rows))
    return 0


def _cmd_numerics(args: argparse.Namespace) -> int:
    from sim_core.numerics.convergence import grid_study
    from sim_core.numerics.report import (
        SECTION,
        load_grid,
        plot_grid,
        save_grid,
        update_numerics_doc,
    )

    if args.solver_options:
        return _cmd_solver_options()
    doc = doc_to_update(args, "docs/NUMERICS.md", SECTION)
    # a quick grid never overwrites the committed full one
    out = out_folder(args.out or ("out/numerics-quick" if args.quick else RESULTS_DIR), "--out")
    if args.from_json:
        try:
            points, info = load_grid(Path(args.from_json))
        except KeyError as exc:
            raise UsageError(f"--from-json {args.from_json}: not a numerics.json (no {exc} "
                             "entry)") from None  # fmt: skip
        except (OSError, ValueError, TypeError) as exc:
            raise UsageError(f"--from-json {args.from_json}: {one_line(exc)}") from None
    elif args.quick:
        points, info = grid_study(dts=(1e-3, 2e-4, 1e-4, 5e-5), inits=(1.0,), duration_s=2.0,
                                  progress=print, with_batch=False, check_reference=False,
                                  drift_reference=("implicitfast", 2.5e-5),
                                  drift_d31s=(1.9, 2.9))  # fmt: skip
    else:
        points, info = grid_study(progress=print)
    plot_grid(points, out / "numerics_pareto.png", out / "numerics_map.png", info)
    save_grid(out / "numerics.json", points, info)
    print(f"wrote {out / 'numerics_pareto.png'}, {out / 'numerics_map.png'}, numerics.json")
    if doc is not None:
        doc.write_text(update_numerics_doc(doc.read_text(), points, info))
        print(f"updated the grid table in {doc}")
    return 0


def register(sub: Any) -> None:
    _add_bench(sub)
    _add_converge(sub)
    _add_numerics(sub)

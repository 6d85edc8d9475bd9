"""`insect-gait` command line: a thin layer over the public API.

Subcommands of packages that sim_core must not import (the REST service, the viewer) arrive
through the entry-point group `insect_gait.commands`; each entry point is a
`register(subparsers)` function.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence
from importlib.metadata import entry_points
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from sim_core.params import INTEGRATORS
from sim_core.spec import RunSpec

EXIT_USAGE = 2


class _Parser(argparse.ArgumentParser):
    """argparse that reports errors in one line and exits 2 (never a traceback)."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\n")


def _add_run(sub: Any) -> None:
    p = sub.add_parser("run", help="simulate one walk and report Delta31 and the gait")
    p.add_argument("--beta", type=float, required=True, help="duty factor in (0.5, 1)")
    p.add_argument("--d31-init", type=float, default=2.0 * math.pi / 3.0, help="rad")
    p.add_argument("--duration-s", type=float, default=5.0)
    p.add_argument("--body-mass-g", type=float, default=3.0)
    p.add_argument("--slope-deg", type=float, default=0.0, help="uphill positive")
    p.add_argument("--integrator", choices=INTEGRATORS, default=None)
    p.add_argument("--dt-s", type=float, default=None, help="physics timestep")
    p.add_argument("--control-dt-s", type=float, default=None, help="controller period")
    p.add_argument("--no-phase-reset", action="store_true", help="disable eq. 4")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_cmd_run)


def _spec_from_args(args: argparse.Namespace) -> RunSpec:
    return RunSpec(
        beta=args.beta,
        d31_init=args.d31_init % (2 * math.pi) if math.isfinite(args.d31_init) else args.d31_init,
        duration_s=args.duration_s,
        body_mass_g=args.body_mass_g,
        slope_deg=args.slope_deg,
        phase_reset=not args.no_phase_reset,
        integrator=args.integrator,
        dt_s=args.dt_s,
        control_dt_s=args.control_dt_s,
    )


def _validation_message(exc: ValidationError) -> str:
    parts = []
    for err in exc.errors():
        field = ".".join(str(x) for x in err["loc"]) or "arguments"
        parts.append(f"--{field.replace('_', '-')}: {err['msg']}")
    return "; ".join(parts)


def _cmd_run(args: argparse.Namespace) -> int:
    from sim_core.runner import simulate

    try:
        spec = _spec_from_args(args)
    except ValidationError as exc:
        print(f"insect-gait run: error: {_validation_message(exc)}", file=sys.stderr)
        return EXIT_USAGE
    result = simulate(spec)
    summary = result.summary()
    if args.json:
        print(json.dumps(summary))
    else:
        _print_summary(result.summary(), spec)
    return 0 if not result.diverged else 1


def _print_summary(s: dict[str, Any], spec: RunSpec) -> None:
    from sim_core.params import ModelParams, nominal_speed

    p = ModelParams()
    v_nom = nominal_speed(spec.beta, p.stroke, p.swing_duration) * 100
    if s["diverged"]:
        print(f"DIVERGED: {s['error']}")
        return
    d31 = s["d31"]
    print(f"beta {spec.beta:.3f}  d31_init {spec.d31_init:.3f} rad  duration {spec.duration_s} s")
    print(f"Delta31 at leg-1 touchdowns ({len(d31)}): " + " ".join(f"{x:.2f}" for x in d31[-12:]))
    final = "n/a" if s["d31_final"] is None else f"{s['d31_final']:.3f} rad"
    print(f"final Delta31 {final}  gait {s['gait']}")
    if s["speed_cm_s"] is not None:
        print(f"speed {s['speed_cm_s']:.2f} cm/s (eq. 2: {v_nom:.2f})")
    if s["duty_factor_measured"] is not None:
        print(f"duty factor measured {s['duty_factor_measured']:.3f} (commanded {spec.beta:.3f})")
    if s["slip_fraction"] is not None:
        print(f"foot slip per stance {100 * s['slip_fraction']:.1f}% of the stroke")
    if s["landing_swing_share"] is not None:
        print(f"feet land at {s['landing_swing_share']:.2f} of their swing (1 = at the AEP)")
    if s["retouches_per_stance"] is not None:
        print(f"stance feet leave and re-touch the ground {s['retouches_per_stance']:.2f} times "
              "per stance")  # fmt: skip


def _add_bench(sub: Any) -> None:
    p = sub.add_parser("bench", help="speed of one and many simulations, side by side")
    p.add_argument("--json", action="store_true")
    p.add_argument("--sim-seconds", type=float, default=2.0, help="per measurement")
    p.add_argument("--nsim", type=int, default=32, help="batch size")
    p.set_defaults(func=_cmd_bench)


def _cmd_bench(args: argparse.Namespace) -> int:
    from sim_core.bench import run_bench

    if args.sim_seconds <= 0 or args.nsim < 1:
        print("insect-gait bench: error: --sim-seconds > 0 and --nsim >= 1", file=sys.stderr)
        return EXIT_USAGE
    report = run_bench(sim_seconds=args.sim_seconds, nsim=args.nsim, verbose=not args.json)
    if args.json:
        print(json.dumps(report))
    return 0


def _add_params(sub: Any) -> None:
    p = sub.add_parser("params", help="every model parameter with its origin and reason")
    p.add_argument("--json", action="store_true")
    p.add_argument("--update-doc", metavar="MD", help="rewrite the table in this markdown file")
    p.set_defaults(func=_cmd_params)


def _cmd_params(args: argparse.Namespace) -> int:
    from sim_core.params import parameter_markdown, parameter_table, update_parameter_doc

    if args.update_doc:
        path = Path(args.update_doc)
        path.write_text(update_parameter_doc(path.read_text()))
        return 0
    if args.json:
        rows = [
            {"name": n, "value": v, "origin": o, "reason": r} for n, v, o, r in parameter_table()
        ]
        print(json.dumps(rows, indent=1))
    else:
        print(parameter_markdown())
    return 0


def _add_calibrate(sub: Any) -> None:
    p = sub.add_parser(
        "calibrate", help="search the open parameters for the paper's gait selection"
    )
    p.add_argument("--trials", type=int, default=50)
    p.add_argument("--storage", default="sqlite:///out/calibration.db", help="optuna storage URL")
    p.add_argument("--study", default="gait-selection")
    p.add_argument("--duration-s", type=float, default=6.0, help="per run")
    p.add_argument("--n-init", type=int, default=8, help="initial Delta31 values per beta")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--seed-from", default=None, help="re-score an earlier study's trials first")
    p.add_argument(
        "--no-half-dt-check", action="store_true", help="skip scoring at half the timestep"
    )
    p.add_argument(
        "--start-from",
        default=None,
        help="JSON file: a list of parameter sets to evaluate before sampling (warm start)",
    )
    p.add_argument(
        "--betas", type=float, nargs="+", default=[0.62, 0.655, 0.70], help="betas to score"
    )
    p.add_argument(
        "--objective",
        choices=["closed-loop", "drift", "pull"],
        default="closed-loop",
        help="closed-loop: settled Delta31 of many runs; drift: open-loop drift signs (cheaper);"
        " pull: how close short runs end to the branches, walking-sanity penalties, wider space",
    )
    p.set_defaults(func=_cmd_calibrate)


def _cmd_calibrate(args: argparse.Namespace) -> int:
    import time

    from sim_core.calibration import SEARCH_SPACE, calibrate
    from sim_core.pull import WIDE_SPACE

    if args.trials < 1 or args.duration_s <= 0 or args.n_init < 2:
        print("insect-gait calibrate: error: --trials >= 1, --duration-s > 0, --n-init >= 2",
              file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    if args.storage.startswith("sqlite:///"):
        Path(args.storage.removeprefix("sqlite:///")).parent.mkdir(parents=True, exist_ok=True)
    start_from = json.loads(Path(args.start_from).read_text()) if args.start_from else []
    t0 = time.perf_counter()

    def report(n: int, score: float, values: dict[str, float]) -> None:
        shown = " ".join(f"{k}={v:.3g}" for k, v in values.items())
        print(f"[{time.perf_counter() - t0:7.0f} s] trial {n}: score {score:.3f}  {shown}",
              flush=True)  # fmt: skip

    study = calibrate(
        args.trials, storage=args.storage, study_name=args.study, seed=args.seed,
        duration_s=args.duration_s, n_init=args.n_init, on_trial=report,
        betas=tuple(args.betas), seed_from=args.seed_from,
        check_half_dt=not args.no_half_dt_check, objective_name=args.objective,
        start_from=start_from,
    )  # fmt: skip
    best = study.best_trial
    print(f"best trial {best.number}: score {best.value:.3f}")
    for k in WIDE_SPACE if args.objective == "pull" else SEARCH_SPACE:
        print(f"  {k} = {best.params[k]:.4g}")
    return 0


def _add_return_map(sub: Any) -> None:
    p = sub.add_parser("return-map", help="Delta31(n) -> Delta31(n+4) drift from many starts")
    p.add_argument("--beta", type=float, required=True)
    p.add_argument("--n-init", type=int, default=16)
    p.add_argument("--duration-s", type=float, default=3.0)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_return_map)


def _cmd_return_map(args: argparse.Namespace) -> int:
    import numpy as np

    from sim_core.calibration import initial_values, return_map

    if not 0.5 < args.beta < 1 or args.n_init < 1 or args.duration_s <= 0:
        print("insect-gait return-map: error: beta in (0.5, 1), --n-init >= 1, --duration-s > 0",
              file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    inits = initial_values(args.n_init).tolist()
    rm = return_map(None, args.beta, inits, duration_s=args.duration_s)
    centers, drift = rm.drift_per_cycle()
    if args.json:
        drift_list = [None if np.isnan(d) else float(d) for d in drift]
        obj = {"beta": args.beta, "x": rm.x.tolist(), "y": rm.y.tolist()}
        obj.update({"bin_centers": centers.tolist(), "drift_per_cycle": drift_list})
        print(json.dumps(obj))
        return 0
    print(f"beta {args.beta}: {rm.x.size} pairs; mean drift of Delta31 per cycle by bin")
    for c, d in zip(centers, drift, strict=True):
        bar = "" if np.isnan(d) else ("+" if d > 0 else "-") * min(40, int(abs(d) / 0.005))
        shown = "   n/a" if np.isnan(d) else f"{d:+.3f}"
        print(f"  {c:5.2f} rad  {shown}  {bar}")
    return 0


def _add_converge(sub: Any) -> None:
    p = sub.add_parser("converge", help="same gait outcomes at dt and dt/2? (default numerics)")
    p.add_argument("--dt-s", type=float, default=None)
    p.add_argument("--integrator", choices=INTEGRATORS, default=None)
    p.add_argument("--duration-s", type=float, default=6.0)
    p.add_argument("--tolerance", type=float, default=0.05, help="rad")
    p.set_defaults(func=_cmd_converge)


def _cmd_converge(args: argparse.Namespace) -> int:
    from sim_core.numerics import convergence_check

    if (args.dt_s is not None and args.dt_s <= 0) or args.duration_s <= 0:
        print("insect-gait converge: error: --dt-s and --duration-s must be > 0", file=sys.stderr)
        return EXIT_USAGE
    report = convergence_check(
        dt_s=args.dt_s, integrator=args.integrator, duration_s=args.duration_s
    )
    print(report.summary(args.tolerance))
    return 0 if all(report.agree(args.tolerance)) else 1


def _add_study(sub: Any) -> None:
    p = sub.add_parser("study", help="gait-selection evidence for the defaults: figures + JSON")
    p.add_argument("--out", default="docs/figures", help="output folder")
    p.add_argument("--quick", action="store_true", help="fewer, shorter runs; no sensitivity")
    p.add_argument("--no-sensitivity", action="store_true")
    p.set_defaults(func=_cmd_study)


def _cmd_study(args: argparse.Namespace) -> int:
    from sim_core.study import run_study

    if args.quick:
        run_study(Path(args.out), n_init=4, duration_s=2.0, map_inits=6, map_duration_s=1.5,
                  with_sensitivity=False)  # fmt: skip
    else:
        run_study(Path(args.out), with_sensitivity=not args.no_sensitivity)
    return 0


def _doc_to_update(args: argparse.Namespace, default: str) -> Path | None:
    """The markdown file a generating command rewrites its section of: --doc, else `default`
    for a full run; none with --no-doc, or with --quick unless --doc names one."""
    if args.no_doc or not (args.doc or not args.quick):
        return None
    doc = Path(args.doc or default)
    if not doc.is_file():
        raise FileNotFoundError(f"--doc {doc}: no such file")
    return doc


def _add_numerics(sub: Any) -> None:
    p = sub.add_parser("numerics", help="integrator x timestep grid against RK4 at 2e-5 s")
    p.add_argument("--quick", action="store_true", help="a coarse grid, short runs")
    p.add_argument(
        "--out", default=None, help="folder (default docs/figures; --quick: out/numerics-quick)"
    )
    p.add_argument("--doc", default=None,
                   help="markdown file whose numerics section to regenerate (default "
                   "docs/NUMERICS.md; none with --quick)")  # fmt: skip
    p.add_argument("--no-doc", action="store_true", help="do not touch any markdown file")
    p.add_argument("--from-json", default=None, metavar="PATH",
                   help="redraw figures and table from a numerics.json; no simulation")  # fmt: skip
    p.set_defaults(func=_cmd_numerics)


def _cmd_numerics(args: argparse.Namespace) -> int:
    from sim_core.numerics import grid_study
    from sim_core.numerics_report import load_grid, plot_grid, save_grid, update_numerics_doc

    prog = "insect-gait numerics"
    # a quick grid never overwrites the committed full one
    out = Path(args.out or ("out/numerics-quick" if args.quick else "docs/figures"))
    try:
        doc = _doc_to_update(args, "docs/NUMERICS.md")
    except FileNotFoundError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    out.mkdir(parents=True, exist_ok=True)
    if args.from_json:
        try:
            points, info = load_grid(Path(args.from_json))
        except (OSError, ValueError, KeyError, TypeError) as exc:
            print(f"{prog}: error: --from-json {args.from_json}: {exc}", file=sys.stderr)
            return EXIT_USAGE
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


def _add_reproduce(sub: Any) -> None:
    from sim_core.backends import BACKENDS
    from sim_core.paper_figures import FIGURES

    p = sub.add_parser(
        "reproduce", help="the paper's Figs. 5-9 + ablation: figures, data, reproduction table"
    )
    p.add_argument("--figure", nargs="+", choices=[*FIGURES, "all"], default=["all"],
                   help="which figures (default all)")  # fmt: skip
    p.add_argument(
        "--out", default=None, help="folder (default docs/figures; --quick: out/reproduce-quick)"
    )
    p.add_argument("--cache", default="out/cache", help="task result cache folder")
    p.add_argument("--backend", choices=BACKENDS, default="local",
                   help="local: process pool on this machine; dask: dask.distributed")  # fmt: skip
    p.add_argument("--address", default=None, help="dask scheduler, e.g. tcp://host:8786")
    p.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    p.add_argument("--quick", action="store_true", help="tiny sizes: a smoke test, not science")
    p.add_argument("--doc", default=None,
                   help="markdown file whose reproduce section to regenerate (default "
                   "docs/REPRODUCTION.md; none with --quick)")  # fmt: skip
    p.add_argument("--no-doc", action="store_true", help="do not touch any markdown file")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_reproduce)


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from sim_core.backends import BackendUnavailable, get_backend
    from sim_core.paper_figures import Config
    from sim_core.reproduce import reproduce

    prog = "insect-gait reproduce"
    if args.workers is not None and args.workers < 1:
        print(f"{prog}: error: --workers must be >= 1", file=sys.stderr)
        return EXIT_USAGE
    cfg = Config.quick() if args.quick else Config()
    out = Path(args.out or ("out/reproduce-quick" if args.quick else "docs/figures"))
    try:
        doc = _doc_to_update(args, "docs/REPRODUCTION.md")
    except FileNotFoundError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    try:
        backend = get_backend(args.backend, args.workers, args.address)
    except BackendUnavailable as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
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


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="insect-gait", description=__doc__.splitlines()[0] if __doc__ else "")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    _add_run(sub)
    _add_bench(sub)
    _add_params(sub)
    _add_calibrate(sub)
    _add_return_map(sub)
    _add_converge(sub)
    _add_study(sub)
    _add_numerics(sub)
    _add_reproduce(sub)
    for ep in entry_points(group="insect_gait.commands"):
        try:
            register = ep.load()
        except ImportError as exc:  # a plug-in whose extra deps are missing: say so, go on
            sub.add_parser(ep.name, help=f"unavailable: {exc}")
            continue
        register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    func = getattr(args, "func", None)
    if func is None:
        parser.error(f"command {args.command!r} is not available")
    return int(func(args))


if __name__ == "__main__":
    sys.exit(main())

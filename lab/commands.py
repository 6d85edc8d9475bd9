"""`calibrate` and `sensitivity`: searches and robustness studies of the open parameters."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from sim_core import default_cache_dir
from sim_core.cli import EXIT_USAGE
from sim_core.contract import RESULTS_DIR


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

    from lab.calibrate import SEARCH_SPACE, calibrate
    from lab.space import WIDE_SPACE

    if args.trials < 1 or args.duration_s <= 0 or args.n_init < 2:
        print("python -m lab calibrate: error: --trials >= 1, --duration-s > 0, --n-init >= 2",
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


def _add_sensitivity(sub: Any) -> None:
    p = sub.add_parser("sensitivity", help="+-10%% of each open parameter: tornado chart + JSON")
    p.add_argument(
        "--out", default=RESULTS_DIR, type=Path, help="output folder (default %(default)s)"
    )
    p.add_argument("--n-init", type=int, default=8, help="initial Delta31 values per beta")
    p.add_argument("--duration-s", type=float, default=6.0, help="per run")
    p.set_defaults(func=_cmd_sensitivity)


def _cmd_sensitivity(args: argparse.Namespace) -> int:
    from lab.sensitivity import run_sensitivity

    if args.n_init < 1 or args.duration_s <= 0:
        print("python -m lab sensitivity: error: --n-init >= 1, --duration-s > 0", file=sys.stderr)
        return EXIT_USAGE
    run_sensitivity(Path(args.out), n_init=args.n_init, duration_s=args.duration_s)
    return 0


def _add_diagnose(sub: Any) -> None:
    p = sub.add_parser(
        "diagnose", help="body modes, support-stiffness ratio, load share with Delta31 held"
    )
    p.add_argument("--params", default="{}", help="JSON overrides, e.g. '{\"com_offset_x\": 1e-3}'")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_diagnose)


def _cmd_diagnose(args: argparse.Namespace) -> int:
    from pydantic import ValidationError

    from lab.diagnostics import diagnose
    from sim_core import ModelParams

    try:
        params = ModelParams.of(**json.loads(args.params))
    except (ValueError, ValidationError) as exc:
        print(f"python -m lab diagnose: error: --params: {exc}", file=sys.stderr)
        return EXIT_USAGE
    report = diagnose(params)
    if args.json:
        print(json.dumps(report, indent=1))
        return 0
    for m in report["body_modes"]:
        if m["frequency_hz"]:
            how = f"{m['frequency_hz']:.0f} Hz, damping ratio {m['damping_ratio']:.2f}"
        else:
            how = f"overdamped, e-folding {m['decay_ms']:.1f} ms"
        print(f"body {m['name']:5s}: {how}")
    sup = report["support"]
    ks = ", ".join(f"{k} {v:.1f}" for k, v in sup["k_pair_N_per_m"].items())
    print(f"support stiffness per pair (N/m): {ks}; r = k_middle / mean(fore, hind) = "
          f"{sup['ratio_r']:.2f}")  # fmt: skip
    for beta, ls in report["load_share"].items():
        sh = ", ".join(f"{k} {v:.3f}" for k, v in ls["share"].items())
        print(f"beta {beta}: load share {sh}; mean pitch {ls['mean_pitch_mrad']:+.2f} mrad")
    return 0


def register(sub: Any) -> None:
    _add_calibrate(sub)
    _add_sensitivity(sub)
    _add_diagnose(sub)
    _add_slope_heading(sub)
    _add_timing_lines(sub)
    _add_readings(sub)


def _param_overrides(command: str, text: str) -> dict[str, Any] | None:
    """The --params JSON as ModelParams overrides, or None after printing why they are not."""
    from pydantic import ValidationError

    from sim_core import ModelParams

    try:
        over = json.loads(text)
        ModelParams.of(**over)
    except (ValueError, TypeError, ValidationError) as exc:
        print(f"python -m lab {command}: error: --params: {exc}", file=sys.stderr)
        return None
    return dict(over)


def _add_slope_heading(sub: Any) -> None:
    p = sub.add_parser(
        "slope-heading",
        help="does the body keep its heading on a slope? (per ground and no-slip setting)",
    )
    p.add_argument("--slopes", type=float, nargs="+", default=[-20.0, 20.0])
    p.add_argument("--duration-s", type=float, default=60.0)
    p.add_argument("--noslip", type=int, nargs="*", default=[0, 10],
                   help="no-slip passes, constraint ground (default %(default)s; none: skip "
                   "that ground)")  # fmt: skip
    p.add_argument(
        "--friction",
        type=float,
        nargs="+",
        default=[1.0],
        help="foot friction coefficients, constraint ground (default %(default)s)",
    )
    p.add_argument("--penalty", action="store_true", help="also the paper's ground")
    p.add_argument(
        "--params",
        default="{}",
        help="JSON overrides for every setting, e.g. '{\"com_offset_x\": 3e-3}'",
    )
    p.set_defaults(func=_cmd_slope_heading)


def _cmd_slope_heading(args: argparse.Namespace) -> int:
    import time

    from lab.slope_heading import headings, table
    from sim_core import ModelParams

    if not 0 < args.duration_s <= 600:
        print("python -m lab slope-heading: error: --duration-s in (0, 600]", file=sys.stderr)
        return EXIT_USAGE
    if any(f <= 0 for f in args.friction) or any(n < 0 for n in args.noslip):
        print("python -m lab slope-heading: error: --friction > 0, --noslip >= 0", file=sys.stderr)
        return EXIT_USAGE
    over = _param_overrides("slope-heading", args.params)
    if over is None:
        return EXIT_USAGE
    from lab.readings import settings_name

    tag = settings_name("", over)
    default_mu = ModelParams().contact.friction
    settings = [
        (
            f"constraint, noslip {n}" + ("" if mu == default_mu else f", friction {mu:g}") + tag,
            ModelParams.of(**{"noslip_iterations": n, "friction": mu, **over}),
        )
        for n in args.noslip
        for mu in args.friction
    ]
    if args.penalty:
        settings.append(("paper's ground" + tag, ModelParams.of(**{"ground": "penalty", **over})))
    at = [t for t in (10.0, 20.0, 30.0, 40.0, 50.0, 60.0) if t <= args.duration_s]
    t0 = time.perf_counter()
    runs = headings(settings, args.slopes, duration_s=args.duration_s, at_s=at)
    print("\n".join(table(runs, at)))
    print(f"\n{time.perf_counter() - t0:.0f} s wall")
    return 0


def _add_timing_lines(sub: Any) -> None:
    p = sub.add_parser(
        "timing-lines",
        help="test the two-timing-lines hypothesis (open-loop jumps per leg "
        "pair, the middle lift-off -> hind touchdown lag, the reduced model's branch)",
    )
    p.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.645, 0.70],
                   help="duty factors (default %(default)s)")  # fmt: skip
    p.add_argument("--d-step", type=float, default=0.05,
                   help="step of the held D over 1.4-3.2 rad (default %(default)s)")  # fmt: skip
    p.add_argument("--grounds", nargs="+", choices=["constraint", "penalty"],
                   default=["constraint", "penalty"], help="(default %(default)s)")  # fmt: skip
    p.add_argument(
        "--out",
        type=Path,
        default=Path("out/timing_lines"),
        help="folder for timing_lines.{json,md,png} (default %(default)s)",
    )
    p.add_argument("--skip", nargs="*", choices=["open-loop", "chain", "reduced"], default=[],
                   help="tests to leave out")  # fmt: skip
    p.set_defaults(func=_cmd_timing_lines)


def _cmd_timing_lines(args: argparse.Namespace) -> int:
    import time
    from dataclasses import asdict

    import numpy as np

    from lab import timing_lines as tl
    from sim_core import ModelParams

    if not 0.0 < args.d_step <= 0.5 or not all(0.5 < b < 1.0 for b in args.betas):
        print("python -m lab timing-lines: error: --d-step in (0, 0.5], betas in (0.5, 1)",
              file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    args.out.mkdir(parents=True, exist_ok=True)
    d31s = np.arange(1.4, 3.2 + 1e-9, args.d_step)
    record: dict[str, Any] = {"betas": args.betas, "d31s": d31s.tolist()}
    lines: list[str] = []
    for ground in args.grounds:
        p = ModelParams.of(ground=ground)
        if "open-loop" not in args.skip:
            t0 = time.perf_counter()
            ol = tl.open_loop_legs(p, args.betas, d31s.tolist())
            feats = tl.features(ol)
            record.setdefault("open_loop", []).append(
                {"ground": ground, "fore": ol.fore.tolist(), "middle": ol.middle.tolist(),
                 "hind": ol.hind.tolist(), "spread": ol.spread.tolist(),
                 "features": [asdict(f) for f in feats],
                 "wall_s": time.perf_counter() - t0})  # fmt: skip
            record.setdefault("_loops", []).append(ol)
            lines += [f"open loop, {ground} ground ({time.perf_counter() - t0:.0f} s):", "",
                      *tl.features_table(feats), ""]  # fmt: skip
            print("\n".join(lines[-len(feats) - 4 :]), flush=True)
        if "chain" not in args.skip:
            t0 = time.perf_counter()
            runs = [(b, x) for b in args.betas for x in (1.9, 2.3)]
            chain = tl.chain_lags(p, runs)
            record.setdefault("chain", []).extend(
                asdict(c) | {"lags": None} for c in chain)  # fmt: skip
            lines += [f"chain, {ground} ground ({time.perf_counter() - t0:.0f} s):", "",
                      *tl.chain_table(chain), ""]  # fmt: skip
            print("\n".join(lines[-len(chain) - 4 :]), flush=True)
    if "reduced" not in args.skip:
        t0 = time.perf_counter()
        red = tl.reduced_branches(np.round(np.arange(0.60, 0.7001, 0.01), 3).tolist(),
                                  [3.0, 1.0, 0.1])  # fmt: skip
        record["reduced"] = [asdict(r) for r in red]
        lines += [f"reduced model, equal legs ({time.perf_counter() - t0:.0f} s):", "",
                  *tl.reduced_table(red), ""]  # fmt: skip
        print("\n".join(lines[-len(red) - 4 :]), flush=True)
    loops = record.pop("_loops", [])
    if loops:
        tl.plot_open_loop(loops, str(args.out / "timing_lines.png"))
    (args.out / "timing_lines.json").write_text(json.dumps(record, indent=1))
    (args.out / "timing_lines.md").write_text("\n".join(lines))
    print(f"wrote {args.out}/timing_lines.{{json,md,png}}")
    return 0


def _add_readings(sub: Any) -> None:
    p = sub.add_parser(
        "readings",
        help="screen the other readings of the paper's text (8 starts per "
        "beta, settled finals and their gaits, per ground)",
    )
    # the names live with the study (lab.readings.READINGS), which loads MuJoCo:
    # checked when the command runs, so that `--help` stays light
    p.add_argument("--readings", nargs="+", default=None,
                   help="which readings (default: all; an unknown name lists them)")  # fmt: skip
    p.add_argument("--grounds", nargs="+", choices=["constraint", "penalty"],
                   default=["constraint", "penalty"], help="(default %(default)s)")  # fmt: skip
    p.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.70])
    p.add_argument("--duration-s", type=float, default=40.0)
    p.add_argument("--stop-if-settled-s", type=float, default=None,
                   help="a run settled by then stops there (a cheaper screen)")  # fmt: skip
    p.add_argument(
        "--params",
        default="{}",
        help="JSON overrides on top of every reading (a lever screened under it), e.g. "
        "'{\"com_offset_x\": 5e-4}'",
    )
    p.add_argument("--finder", action="store_true",
                   help="run the settled fixed-point finder (kicks, borders) instead of the "
                   "census: the instrument behind Fig. 8")  # fmt: skip
    p.add_argument("--robust", action="store_true",
                   help="also a census with each calibrated parameter at 0.9x and 1.1x of "
                   "the setting's value: do the same states live, how far does a fold "
                   "move")  # fmt: skip
    p.add_argument("--cache", default=str(default_cache_dir()),
                   help="task result cache folder (resumes; default: the installation's, shared "
                   "with the CLI and the API)")  # fmt: skip
    p.add_argument("--backend", choices=["local", "dask"], default="local")
    p.add_argument("--workers", type=int, default=None)
    p.set_defaults(func=_cmd_readings)


def _cmd_readings(args: argparse.Namespace) -> int:
    import time
    from pathlib import Path

    from lab.readings import (
        READINGS,
        find_states,
        finder_table,
        screen,
        settings_name,
        table,
        variants,
    )
    from sim_core import ResultCache, get_backend

    if not 0 < args.duration_s <= 600 or not all(0.5 < b < 1.0 for b in args.betas):
        print("python -m lab readings: error: --duration-s in (0, 600], betas in (0.5, 1)",
              file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    stop = args.stop_if_settled_s
    if stop is not None and not 0 < stop <= args.duration_s:
        print("python -m lab readings: error: --stop-if-settled-s in (0, --duration-s]",
              file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    over = _param_overrides("readings", args.params)
    if over is None:
        return EXIT_USAGE
    if args.robust and args.finder:
        print("python -m lab readings: error: --robust is a census per variant; run --finder on "
              "the setting alone", file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    names = args.readings or list(READINGS)
    unknown = [n for n in names if n not in READINGS]
    if unknown:
        print(f"python -m lab readings: error: unknown reading(s) {unknown}; choose from "
              f"{list(READINGS)}", file=sys.stderr)  # fmt: skip
        return EXIT_USAGE
    rows: list[str] = []
    cache = ResultCache(Path(args.cache))
    backend = get_backend(args.backend, args.workers)
    try:
        for reading in names:
            for ground in args.grounds:
                levers = variants(reading, ground, over) if args.robust else [over]
                for lever in levers:
                    t0 = time.perf_counter()
                    if args.finder:
                        cells = find_states(reading, ground, args.betas, cache, backend,
                                            over=lever)  # fmt: skip
                        got = finder_table(settings_name(reading, lever), ground, cells)
                    else:
                        got = table(screen(reading, ground, args.betas, cache, backend,
                                           duration_s=args.duration_s, stop_if_settled_s=stop,
                                           over=lever))  # fmt: skip
                    head, body = got[:2], got[2:]
                    rows += body
                    print("\n".join(body), f"({time.perf_counter() - t0:.0f} s)", flush=True)
    finally:
        backend.close()
    print("\n".join(head + rows))
    return 0

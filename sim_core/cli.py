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
    p.set_defaults(func=_cmd_params)


def _cmd_params(args: argparse.Namespace) -> int:
    from sim_core.params import parameter_markdown, parameter_table

    if args.json:
        rows = [
            {"name": n, "value": v, "origin": o, "reason": r} for n, v, o, r in parameter_table()
        ]
        print(json.dumps(rows, indent=1))
    else:
        print(parameter_markdown())
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="insect-gait", description=__doc__.splitlines()[0] if __doc__ else "")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    _add_run(sub)
    _add_bench(sub)
    _add_params(sub)
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

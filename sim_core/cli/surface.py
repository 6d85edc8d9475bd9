"""`surface` (the drift surface: every gait, stable and unstable, from walks held at each
Delta31) and `surface-check` (the surface against the fixed-point finder's settled runs), and
what they share with `atlas` (sim_core/cli/atlas.py): the held grid, the pin, the run's
options (generated from RunSpec, bar what a probe sets itself) and the model's parameters."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from sim_core.cli.common import EXIT_USAGE, UsageError, one_line, out_file
from sim_core.cli.model import add_model_args, choice_from_args, model_line
from sim_core.cli.paper import add_backend_args, backend_from_args, cache_from_args
from sim_core.cli.runflags import add_run_flags, run_fields, validation_message
from sim_core.contract.results import BIFURCATION_FILE, RESULTS_DIR
from sim_core.model.spec import numerics_problem, pin_problem

# the betas the surface is validated at: the Fig. 7 betas and the two ends of the paper's window
CHECK_BETAS = (0.62, 0.64, 0.655, 0.675, 0.70)
# what a probe sets itself (`probe_spec`): beta (--beta), the start and the pin at each held
# Delta31 (--d31), the pin's gain (--gain-per-s: the protocol's), its length (the protocol's
# settle and averaging times) and no early stop (a probe averages a fixed window). Every other
# field of RunSpec is a flag of `surface`, `surface-check` and `atlas` and reaches every probe.
SURFACE_VARIES = ("beta", "d31_init", "pin_d31", "pin_gain_per_s", "duration_s",
                  "stop_if_settled_s")  # fmt: skip


SURFACE_HELP = (
    "The drift surface at each duty factor: walks with Delta31 held near each value of a grid "
    "(a weak pin, phase resets on), each measuring how fast Delta31 would drift per gait cycle "
    "if let go. Where the drift falls through zero as Delta31 rises is a stable gait (runs "
    "from either side settle there); where it rises through zero, an unstable one (the border "
    "between two gaits). The first pass is bisected near zeros and dips of the drift. Prints, "
    "per beta, each zero in words and the folds where a stable branch ends; --json prints the "
    "whole surface. Every probe is cached (--cache), so an interrupted or repeated command "
    "reads them back. docs/MODEL.md, 'Instruments', has the method."
)


def _grid(text: str) -> tuple[float, float, float]:
    """argparse type for LO:HI:STEP (rad)."""
    try:
        lo, hi, step = (float(x) for x in text.split(":"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not LO:HI:STEP, e.g. 1.3:3.5:0.1") from None
    if not (0.0 <= lo < hi < 6.2832 and 0.0 < step <= hi - lo + 1e-9):
        raise argparse.ArgumentTypeError(
            f"{text!r}: need 0 <= LO < HI < 2 pi and 0 < STEP <= HI - LO (rad)"
        )
    return lo, hi, step


def _default_grid() -> str:
    from sim_core.contract.surface import SurfaceConfig

    g = SurfaceConfig().d31_grid
    return f"{g[0]:g}:{g[-1]:g}:{round(g[1] - g[0], 6):g}"


def add_surface_args(p: Any) -> None:
    """The held grid and the pin's gain, the run's options (RunSpec's fields bar
    SURFACE_VARIES), the model's parameters, refinement, where probes run, progress."""
    from sim_core.runs import BACKENDS

    p.add_argument(
        "--d31",
        type=_grid,
        default=None,
        metavar="LO:HI:STEP",
        help=f"the held Delta31 values of the first pass, rad (default {_default_grid()}, "
        "then bisected near zeros and dips of the drift)",
    )
    p.add_argument(
        "--gain-per-s",
        type=float,
        default=None,
        help="the pin's gain K, 1/s (default 30: see docs/MODEL.md, Instruments)",
    )
    add_run_flags(p, vary=SURFACE_VARIES)
    add_model_args(p)
    p.add_argument(
        "--no-refine",
        action="store_true",
        help="the first pass only: no bisection near zeros and dips, no finer, longer "
        "probes inside unresolved zeros and near-zero bands",
    )
    add_backend_args(p, [b for b in BACKENDS if b != "ray"])
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


def register(sub: Any) -> None:
    p = sub.add_parser(
        "surface",
        help="the drift surface: zeros of Delta31's drift per cycle (gaits, stable and "
        "unstable) and folds, from walks held at each Delta31",
        description=SURFACE_HELP,
    )
    p.add_argument("--beta", type=float, nargs="+", required=True, help="duty factors")
    add_surface_args(p)
    p.add_argument("--json", action="store_true", help="print the whole surface as JSON")
    p.add_argument("--out", default=None, help="also write the surface's JSON to this file")
    p.set_defaults(func=_cmd_surface)

    c = sub.add_parser(
        "surface-check",
        help="the drift surface against the finder's settled runs (docs/figures/"
        "bifurcation.json): stable zeros within 0.03 rad, borders within 0.05",
    )
    c.add_argument("--beta", type=float, nargs="+", default=list(CHECK_BETAS))
    c.add_argument(
        "--finder",
        default=str(RESULTS_DIR / BIFURCATION_FILE),
        help="the finder's output (default %(default)s)",
    )
    c.add_argument(
        "--robust",
        action="store_true",
        help="instead: the surface at 0.9 and 1.1 of each calibrated parameter (default betas "
        "0.62 0.655 0.70): which stable zeros survive, and how far they move",
    )
    add_surface_args(c)
    c.add_argument("--out", default=None, help="also write the surface's JSON to this file")
    c.set_defaults(func=_cmd_check)


def surface_config(args: argparse.Namespace) -> Any:
    """The probes' protocol (`SurfaceConfig`) with --d31 and --gain-per-s."""
    from dataclasses import replace

    from sim_core.paper.surface import SurfaceConfig, grid

    cfg = SurfaceConfig()
    if args.d31 is not None:
        cfg = replace(cfg, d31_grid=grid(*args.d31))
    if args.gain_per_s is not None:
        cfg = replace(cfg, gain_per_s=args.gain_per_s)
    return cfg


def check_probes(betas: list[float], cfg: Any, fields: dict[str, Any]) -> None:
    """Every probe's spec valid and its numerics stable (checked before anything runs, by
    RunSpec's rules and the REST API's words, each refused field named by its flag); a
    UsageError otherwise."""
    from pydantic import ValidationError

    from sim_core.contract.template import RunTemplate
    from sim_core.paper.surface import Probe, probe_spec

    problem = pin_problem(cfg.d31_grid[0], fields.get("phase_reset", True))
    if problem:  # the REST kinds' words (`Held`): the pin is the probes', not the person's
        raise UsageError(f"--no-phase-reset: {problem}")
    try:
        for b in betas:
            for d in (cfg.d31_grid[0], cfg.d31_grid[-1]):
                probe_spec(Probe(b, d, cfg.average_s), cfg, RunTemplate.model_validate(fields))
    except ValidationError as exc:
        raise UsageError(validation_message(exc)) from None
    problem = numerics_problem(fields.get("integrator"), fields.get("dt_s"),
                               fields.get("control_dt_s"))  # fmt: skip
    if problem:
        raise UsageError(f"--dt-s: {problem}")


def say_interrupted(prog: str, cache: str) -> None:
    import sys

    print(
        f"{prog}: interrupted; finished probes are cached in {cache}: run the same command "
        "again to resume",
        file=sys.stderr,
    )


def _run(args: argparse.Namespace, prog: str) -> Any:
    """The surface the arguments ask for (a UsageError names what they got wrong), with the
    model's setting recorded beside the parameters the core records. Its progress bar is
    labelled with the command's name (`prog`'s last word)."""
    from sim_core.contract.template import RunTemplate
    from sim_core.paper.surface import drift_surface

    cfg = surface_config(args)
    choice = choice_from_args(args)
    fields = run_fields(args)
    check_probes(args.beta, cfg, fields)
    backend = backend_from_args(args, prog)
    if backend is None:
        return None
    try:
        surface = drift_surface(
            sorted(args.beta),
            cache=cache_from_args(args),
            backend=backend,
            config=cfg,
            params=choice.model_params(),
            template=RunTemplate.model_validate(fields),
            refine=not args.no_refine,
            progress=False if args.no_progress else prog.split()[-1],
        )
    except KeyboardInterrupt:
        say_interrupted(prog, args.cache)
        raise SystemExit(130) from None
    finally:
        backend.close()
    return surface.model_copy(update={"setting": choice.setting})


# what `describe`'s words mean, said once under its lines (only the words it used)
WORDS = {
    "stable": "stable X: the drift of Delta31 per gait cycle falls through zero at X rad as "
    "Delta31 rises: a gait (walks started on either side of X settle on it)",
    "unstable": "unstable X: the drift rises through zero: the border between two gaits",
    "unresolved": "unresolved (LO-HI): the zero lies somewhere between the probes at LO and HI "
    "(the bisection could not narrow it)",
    "near-zero band": "near-zero band LO-HI: between LO and HI the drift stays inside the noise "
    "floor ({floor:g} mrad per cycle, or 3 standard errors where larger) and has the same sign on "
    "both sides: the ghost of a gait, a tangency, or two zeros too close to tell apart",
}


def describe(surface: Any) -> str:
    """Zeros per beta, then folds, in words; a legend of the words used ends it."""
    lines = []
    used: set[str] = set()
    for b in surface.betas:
        zs = surface.zeros_at(b)
        parts = [
            f"{'stable' if z.stable else 'unstable'} {z.d31:.3f}"
            + ("" if z.resolved else f" (unresolved, {z.lo:.2f}-{z.hi:.2f})")
            for z in zs
        ]
        used.update("stable" if z.stable else "unstable" for z in zs)
        used.update("unresolved" for z in zs if not z.resolved)
        bands = [n for n in surface.near_zeros if abs(n.beta - b) < 1e-9]
        parts += [
            f"near-zero band {n.lo:.2f}-{n.hi:.2f} (drift {'+' if n.sign > 0 else '-'}, "
            f"smallest {n.min_abs_drift * 1e3:.2g} mrad per cycle)"
            for n in bands
        ]
        used.update("near-zero band" for _ in bands)
        bad = [p for p in surface.points_at(b) if not p.usable]
        tail = f"; {len(bad)} probe(s) not used" if bad else ""
        lines.append(f"beta {b:g}: " + (", ".join(parts) or "no zero") + tail)
    for f in surface.folds:
        lines.append(
            f"fold: the branch at {f.d31:.3f} {f.side} between beta {f.beta_lo:g} and "
            f"{f.beta_hi:g}" + ("" if f.resolved else " (its last zero unresolved)")
        )
    lines.append(f"{surface.sim_s:.0f} simulated s in {len(surface.points)} probes")
    floor = 1e3 * surface.config.floor_rad
    lines += [WORDS[w].format(floor=floor) for w in WORDS if w in used]
    return "\n".join(lines)


def _words(surface: Any, args: argparse.Namespace) -> str:
    """The surface in words, and the model's line when it is not the defaults'."""
    return "\n".join(w for w in (describe(surface), model_line(choice_from_args(args))) if w)


def _cmd_surface(args: argparse.Namespace) -> int:
    prog = "insect-gait surface"
    out = out_file(args.out, "--out")
    surface = _run(args, prog)
    if surface is None:
        return EXIT_USAGE
    text = surface.model_dump_json()
    if out is not None:
        out.write_text(text)
    print(json.dumps(json.loads(text)) if args.json else _words(surface, args))
    return 0


def _cmd_check(args: argparse.Namespace) -> int:
    from sim_core.contract.finder import FinderOutput
    from sim_core.paper.surface_check import check, table

    prog = "insect-gait surface-check"
    if args.robust:
        return _cmd_robust(args, prog)
    try:
        finder = FinderOutput.model_validate_json(Path(args.finder).read_text())
    except (OSError, ValueError) as exc:  # pydantic's ValidationError is a ValueError
        raise UsageError(f"--finder {args.finder}: not the finder's output ({one_line(exc)}); "
                         "`insect-gait finder` writes it") from None  # fmt: skip
    out = out_file(args.out, "--out")
    surface = _run(args, prog)
    if surface is None:
        return EXIT_USAGE
    if out is not None:
        out.write_text(surface.model_dump_json())
    rows = check(surface, finder)
    if not rows:
        raise UsageError(f"the finder has none of the betas {args.beta}")
    print(table(rows))
    print(_words(surface, args))
    return 0 if all(r.ok for r in rows) else 1


def _cmd_robust(args: argparse.Namespace, prog: str) -> int:
    import time

    from sim_core.contract.template import RunTemplate
    from sim_core.paper.surface_check import ROBUST_BETAS, robust_surfaces, robust_table

    betas = ROBUST_BETAS if args.beta == list(CHECK_BETAS) else tuple(sorted(args.beta))
    cfg = surface_config(args)
    choice = choice_from_args(args)
    fields = run_fields(args)
    check_probes(list(betas), cfg, fields)
    backend = backend_from_args(args, prog)
    if backend is None:
        return EXIT_USAGE
    t0 = time.perf_counter()
    try:
        surfaces = robust_surfaces(betas, cache=cache_from_args(args), backend=backend,
                                   config=cfg, params=choice.model_params(),
                                   progress=not args.no_progress,
                                   template=RunTemplate.model_validate(fields))  # fmt: skip
    except KeyboardInterrupt:
        say_interrupted(prog, args.cache)
        return 130
    finally:
        backend.close()
    print(robust_table(surfaces))
    sim_s = sum(s.sim_s for s in surfaces.values())
    print(
        f"{len(surfaces)} surfaces, {sim_s:.0f} simulated s, {time.perf_counter() - t0:.0f} s wall"
    )
    if model_line(choice):
        print(model_line(choice))
    return 0

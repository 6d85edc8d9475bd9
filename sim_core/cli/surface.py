"""`surface` (the drift surface: every gait, stable and unstable, from walks held at each
Delta31), `surface-check` (the surface against the fixed-point finder's settled runs) and
`atlas` (the gait atlas from surfaces over beta at each body mass or slope)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from sim_core.cli.common import EXIT_USAGE, UsageError, one_line, out_file, out_folder
from sim_core.cli.paper import add_backend_args, backend_from_args, cache_from_args
from sim_core.contract import GROUND_HELP
from sim_core.contract.results import BIFURCATION_FILE, RESULTS_DIR

# the betas the surface is validated at: the Fig. 7 betas and the two ends of the paper's window
CHECK_BETAS = (0.62, 0.64, 0.655, 0.675, 0.70)
# the atlas from the surface: 13 betas across the paper's window and past it, 0.01 apart
ATLAS_BETAS = tuple(round(0.60 + 0.01 * k, 2) for k in range(13))
# finer near the paper's 3 g and level ground, where the regions change (docs/figures)
ATLAS_VALUES = {
    "mass": (1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 6.0, 8.0),
    "slope": (-20.0, -10.0, -5.0, 0.0, 5.0, 10.0, 20.0),
}
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


def _add_surface_args(p: Any) -> None:
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
        "--ground",
        choices=["constraint", "penalty"],
        default="constraint",
        help=GROUND_HELP,
    )
    p.add_argument(
        "--gain-per-s",
        type=float,
        default=None,
        help="the pin's gain K, 1/s (default 30: see docs/MODEL.md, Instruments)",
    )
    p.add_argument(
        "--dt-s",
        type=float,
        default=None,
        help="physics timestep, s (default: the model's; the dt/2 check halves it)",
    )
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
    p.add_argument("--body-mass-g", type=float, default=3.0, help="body mass, g, 0.5..30")
    p.add_argument("--slope-deg", type=float, default=0.0, help="ground slope, deg, uphill +")
    _add_surface_args(p)
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
    _add_surface_args(c)
    c.add_argument("--out", default=None, help="also write the surface's JSON to this file")
    c.set_defaults(func=_cmd_check)
    a = sub.add_parser(
        "atlas",
        help="the gait atlas from the drift surface: which gaits are stable over beta x body "
        "mass (or slope), and where their branches fold (the viewer's atlas panel)",
    )
    a.add_argument("--axis", choices=["mass", "slope"], required=True)
    a.add_argument(
        "--beta",
        type=float,
        nargs="+",
        default=list(ATLAS_BETAS),
        help="duty factors (default %(default)s)",
    )
    a.add_argument(
        "--values",
        type=float,
        nargs="+",
        default=None,
        help="body masses (g) or slopes (deg) (default: mass "
        + " ".join(f"{v:g}" for v in ATLAS_VALUES["mass"])
        + "; slope "
        + " ".join(f"{v:g}" for v in ATLAS_VALUES["slope"])
        + ")",
    )
    a.add_argument(
        "--out",
        default=str(RESULTS_DIR),
        help="folder for surface_atlas_<axis>_<ground>.json/png (default %(default)s)",
    )
    a.add_argument(
        "--band-pass",
        action="store_true",
        help="also probe finer and longer inside unresolved zeros and near-zero bands (off: "
        "such cells are marked unresolved; the pass costs about 40%% more)",
    )
    a.add_argument(
        "--no-walks",
        action="store_true",
        help="do not decide by settled free walks the cells where an unresolved zero could "
        "change the region (such cells are then marked unresolved)",
    )
    _add_surface_args(a)
    a.set_defaults(func=_cmd_atlas)


def _config(args: argparse.Namespace) -> Any:
    from dataclasses import replace

    from sim_core.paper.surface import SurfaceConfig, grid

    cfg = SurfaceConfig()
    if args.d31 is not None:
        cfg = replace(cfg, d31_grid=grid(*args.d31))
    if args.gain_per_s is not None:
        cfg = replace(cfg, gain_per_s=args.gain_per_s)
    return cfg


def _run(
    args: argparse.Namespace,
    prog: str,
    *,
    sample: tuple[float, ...] | None = None,
    dt_s: float | None = None,
    stats: Any = None,
    **fields: Any,
) -> Any:
    """The surface the arguments ask for, or None after printing why not (exit 2); `sample`
    replaces the held Delta31 grid, `dt_s` the physics step. Its progress bar is labelled
    with the command's name (`prog`'s last word)."""
    from dataclasses import replace

    from sim_core.contract.template import RunTemplate
    from sim_core.model.params import ModelParams
    from sim_core.paper.surface import drift_surface

    cfg = _config(args)
    if sample is not None:
        cfg = replace(cfg, d31_grid=sample)
    dt_s = dt_s if dt_s is not None else getattr(args, "dt_s", None)
    numerics = None if dt_s is None else {"dt_s": dt_s}
    if not _specs_valid(args.beta, cfg, prog, **fields, **(numerics or {})):
        return None
    backend = backend_from_args(args, prog)
    if backend is None:
        return None
    try:
        return drift_surface(
            sorted(args.beta),
            cache=cache_from_args(args),
            backend=backend,
            config=cfg,
            params=ModelParams.of(ground=args.ground),
            template=RunTemplate.model_validate({**fields, **(numerics or {})}),
            refine=not args.no_refine,
            progress=False if args.no_progress else prog.split()[-1],
            stats=stats,
        )
    except KeyboardInterrupt:
        _say_interrupted(prog, args.cache)
        raise SystemExit(130) from None
    finally:
        backend.close()


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


def _cmd_surface(args: argparse.Namespace) -> int:
    prog = "insect-gait surface"
    out = out_file(args.out, "--out")
    surface = _run(args, prog, body_mass_g=args.body_mass_g, slope_deg=args.slope_deg)
    if surface is None:
        return EXIT_USAGE
    text = surface.model_dump_json()
    if out is not None:
        out.write_text(text)
    print(json.dumps(json.loads(text)) if args.json else describe(surface))
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
        print(f"{prog}: error: the finder has none of the betas {args.beta}", file=sys.stderr)
        return EXIT_USAGE
    print(table(rows))
    print(describe(surface))
    return 0 if all(r.ok for r in rows) else 1


def _cmd_robust(args: argparse.Namespace, prog: str) -> int:
    import time

    from sim_core.paper.surface_check import ROBUST_BETAS, robust_surfaces, robust_table

    betas = ROBUST_BETAS if args.beta == list(CHECK_BETAS) else tuple(sorted(args.beta))
    cfg = _config(args)
    if not _specs_valid(list(betas), cfg, prog):
        return EXIT_USAGE
    backend = backend_from_args(args, prog)
    if backend is None:
        return EXIT_USAGE
    t0 = time.perf_counter()
    try:
        surfaces = robust_surfaces(betas, cache=cache_from_args(args), backend=backend,
                                   config=cfg, progress=not args.no_progress)  # fmt: skip
    except KeyboardInterrupt:
        _say_interrupted(prog, args.cache)
        return 130
    finally:
        backend.close()
    print(robust_table(surfaces))
    sim_s = sum(s.sim_s for s in surfaces.values())
    print(
        f"{len(surfaces)} surfaces, {sim_s:.0f} simulated s, {time.perf_counter() - t0:.0f} s wall"
    )
    return 0


def _cmd_atlas(args: argparse.Namespace) -> int:
    import time
    from dataclasses import replace

    from sim_core.contract.results import surface_atlas_file
    from sim_core.model.params import ModelParams
    from sim_core.paper.surface_atlas import draw_atlas, surface_atlas
    from sim_core.paper.surface_walks import WalkConfig
    from sim_core.runs.backends import RunStats

    prog = "insect-gait atlas"
    values = args.values or list(ATLAS_VALUES[args.axis])
    field = "body_mass_g" if args.axis == "mass" else "slope_deg"
    cfg = replace(_config(args), band_pass=args.band_pass)
    if not all(_specs_valid(args.beta, cfg, prog, **{field: v}) for v in values):
        return EXIT_USAGE
    out = out_folder(args.out, "--out")
    backend = backend_from_args(args, prog)
    if backend is None:
        return EXIT_USAGE
    stats = RunStats()
    t0 = time.perf_counter()
    try:
        atlas = surface_atlas(
            args.axis,
            sorted(args.beta),
            values,
            cache=cache_from_args(args),
            backend=backend,
            config=cfg,
            params=ModelParams.of(ground=args.ground),
            refine=not args.no_refine,
            walks=None if args.no_walks else WalkConfig(),
            progress=not args.no_progress,
            stats=stats,
        )
    except KeyboardInterrupt:
        _say_interrupted(prog, args.cache)
        return 130
    finally:
        backend.close()
    wall = time.perf_counter() - t0
    js = surface_atlas_file(out, args.axis, args.ground)
    js.write_text(atlas.model_dump_json())
    draw_atlas(atlas, js.with_suffix(".png"))
    for v in values:
        row = [p for p in atlas.points if p.value == v]
        cells = ", ".join(
            f"{p.beta:g}: {p.region}" + (" (unresolved)" if p.undecided else "") for p in row
        )
        print(f"{args.axis} {v:g}: {cells}")
    print(
        f"{atlas.sim_s:.0f} simulated s ({stats.computed} probes computed, {stats.cached} "
        f"cached) in {wall:.0f} s wall on {backend.name} with {backend.workers} worker(s); "
        f"wrote {js} and .png"
    )
    return 0


def _specs_valid(betas: list[float], cfg: Any, prog: str, **fields: Any) -> bool:
    """Whether every probe's spec is valid (checked before anything runs, in the words the API
    uses: RunSpec's own); if not, says why in one line."""
    from pydantic import ValidationError

    from sim_core.contract.template import RunTemplate
    from sim_core.paper.surface import Probe, probe_spec

    try:
        for b in betas:
            for d in (cfg.d31_grid[0], cfg.d31_grid[-1]):
                probe_spec(Probe(b, d, cfg.average_s), cfg, RunTemplate.model_validate(fields))
    except ValidationError as exc:
        err = exc.errors()[0]
        where = ".".join(str(x) for x in err["loc"]) or "spec"
        print(f"{prog}: error: {where}: {err['msg']}", file=sys.stderr)
        return False
    return True


def _say_interrupted(prog: str, cache: str) -> None:
    print(
        f"{prog}: interrupted; finished probes are cached in {cache}: run the same command "
        "again to resume",
        file=sys.stderr,
    )

"""`surface` (the drift surface: every gait, stable and unstable, from walks held at each
Delta31) and `surface-check` (the surface against the fixed-point finder's settled runs)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from sim_core.cli.common import EXIT_USAGE
from sim_core.cli.paper import _add_backend_args, backend_from_args
from sim_core.paper.results import BIFURCATION_FILE, RESULTS_DIR, SURFACE_FILE

# the betas issue 39 validates at: the Fig. 7 betas and the two ends of the paper's window
CHECK_BETAS = (0.62, 0.64, 0.655, 0.675, 0.70)
# Fig. 8 from the surface: 25 betas, 0.005 apart, around the paper's window 0.62-0.70
FIG8_BETAS = tuple(round(0.60 + 0.005 * k, 3) for k in range(25))
MAP_BETAS = (0.64, 0.655, 0.675)  # Fig. 7
MECHANISM_BETAS = (0.62, 0.655, 0.70)
# the atlas from the surface: 7 betas across the paper's window and past it, 0.02 apart
ATLAS_BETAS = tuple(round(0.60 + 0.02 * k, 2) for k in range(7))
ATLAS_VALUES = {"mass": (1.0, 2.0, 3.0, 4.5, 6.0, 8.0), "slope": (-20.0, -10.0, 0.0, 10.0, 20.0)}


def _grid(text: str) -> tuple[float, float, float]:
    """argparse type for LO:HI:STEP (rad)."""
    try:
        lo, hi, step = (float(x) for x in text.split(":"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not LO:HI:STEP, e.g. 1.3:3.5:0.05") from None
    if not (0.0 <= lo < hi < 6.2832 and 0.0 < step <= hi - lo + 1e-9):
        raise argparse.ArgumentTypeError(
            f"{text!r}: need 0 <= LO < HI < 2 pi and 0 < STEP <= HI - LO (rad)"
        )
    return lo, hi, step


def _add_surface_args(p: Any) -> None:
    from sim_core.runs import BACKENDS

    p.add_argument(
        "--d31",
        type=_grid,
        default=None,
        metavar="LO:HI:STEP",
        help="the held Delta31 values, rad (default 1.3:3.5:0.05)",
    )
    p.add_argument(
        "--ground",
        choices=["constraint", "penalty"],
        default="constraint",
        help="constraint: today's default contact; penalty: the paper's ground",
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
        help="skip the second pass of finer, longer probes inside unresolved zeros "
        "and near-zero bands",
    )
    _add_backend_args(p, [b for b in BACKENDS if b != "ray"])
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


def register(sub: Any) -> None:
    p = sub.add_parser(
        "surface",
        help="the drift surface: zeros of Delta31's drift per cycle (gaits, stable and "
        "unstable) and folds, from walks held at each Delta31",
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
    _add_surface_args(c)
    c.add_argument("--out", default=None, help="also write the surface's JSON to this file")
    c.set_defaults(func=_cmd_check)
    _add_figures(sub)
    a = sub.add_parser(
        "surface-atlas",
        help="the gait atlas from the drift surface: which gaits are stable over beta x body "
        "mass (or slope), and where their branches fold",
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
        help="body masses (g) or slopes (deg) (default: mass 1 2 3 4.5 6 8; slope -20 -10 0 10 20)",
    )
    a.add_argument(
        "--out",
        default=str(RESULTS_DIR),
        help="folder for surface_atlas_<axis>_<ground>.json/png (default %(default)s)",
    )
    _add_surface_args(a)
    a.set_defaults(func=_cmd_atlas)


def _add_figures(sub: Any) -> None:
    f = sub.add_parser(
        "surface-figures",
        help="Figs. 7 and 8 and the mechanism from the drift surface (25 betas 0.60-0.72), "
        "with their reproduction rows",
    )
    f.add_argument(
        "--out",
        default=str(RESULTS_DIR),
        help="folder for surface.json and the PNGs (default %(default)s)",
    )
    f.add_argument(
        "--doc",
        default="docs/REPRODUCTION.md",
        help="markdown file whose 'surface' section to rewrite (default %(default)s)",
    )
    f.add_argument("--no-doc", action="store_true", help="do not touch any markdown file")
    _add_surface_args(f)
    f.set_defaults(func=_cmd_figures, beta=list(FIG8_BETAS), ground="constraint")


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
    replaces the held Delta31 grid, `dt_s` the physics step."""
    from dataclasses import replace

    from sim_core.model.params import ModelParams
    from sim_core.paper.surface import drift_surface
    from sim_core.runs.cache import ResultCache

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
            cache=ResultCache(args.cache),
            backend=backend,
            config=cfg,
            params=ModelParams(ground=args.ground),
            numerics=numerics,
            refine=not args.no_refine,
            progress=not args.no_progress,
            stats=stats,
            **fields,
        )
    except KeyboardInterrupt:
        _say_interrupted(prog, args.cache)
        raise SystemExit(130) from None
    finally:
        backend.close()


def describe(surface: Any) -> str:
    """Zeros per beta, then folds, in words."""
    lines = []
    for b in surface.betas:
        zs = surface.zeros_at(b)
        parts = [
            f"{'S' if z.stable else 'U'} {z.d31:.3f}"
            + ("" if z.resolved else f" (unresolved, {z.lo:.2f}-{z.hi:.2f})")
            for z in zs
        ]
        parts += [
            f"near-zero band {n.lo:.2f}-{n.hi:.2f} (|d| >= {n.min_abs_drift * 1e3:.2f} mrad)"
            for n in surface.near_zeros
            if abs(n.beta - b) < 1e-9
        ]
        bad = [p for p in surface.points_at(b) if not p.usable]
        tail = f"; {len(bad)} probe(s) not used" if bad else ""
        lines.append(f"beta {b:g}: " + (", ".join(parts) or "no zero") + tail)
    for f in surface.folds:
        lines.append(
            f"fold: the branch at {f.d31:.3f} {f.side} between beta {f.beta_lo:g} and "
            f"{f.beta_hi:g}" + ("" if f.resolved else " (its last zero unresolved)")
        )
    lines.append(f"{surface.sim_s:.0f} simulated s in {len(surface.points)} probes")
    return "\n".join(lines)


def _cmd_surface(args: argparse.Namespace) -> int:
    prog = "insect-gait surface"
    surface = _run(args, prog, body_mass_g=args.body_mass_g, slope_deg=args.slope_deg)
    if surface is None:
        return EXIT_USAGE
    text = surface.model_dump_json()
    if args.out:
        Path(args.out).write_text(text)
    print(json.dumps(json.loads(text)) if args.json else describe(surface))
    return 0


def _cmd_check(args: argparse.Namespace) -> int:
    from sim_core.paper.fixedpoints import FinderOutput
    from sim_core.paper.surface_check import check, table

    prog = "insect-gait surface-check"
    try:
        finder = FinderOutput.model_validate_json(Path(args.finder).read_text())
    except (OSError, ValueError) as exc:
        print(f"{prog}: error: --finder {args.finder}: {exc}", file=sys.stderr)
        return EXIT_USAGE
    surface = _run(args, prog)
    if surface is None:
        return EXIT_USAGE
    if args.out:
        Path(args.out).write_text(surface.model_dump_json())
    rows = check(surface, finder)
    if not rows:
        print(f"{prog}: error: the finder has none of the betas {args.beta}", file=sys.stderr)
        return EXIT_USAGE
    print(table(rows))
    print(describe(surface))
    return 0 if all(r.ok for r in rows) else 1


def _cmd_figures(args: argparse.Namespace) -> int:
    import time
    from datetime import date

    from sim_core.docsections import replace_section
    from sim_core.model.params import ModelParams
    from sim_core.paper.reproduce import BETA_TOL
    from sim_core.paper.surface_check import SAMPLE_BETAS, SAMPLE_D31, variant_rows, variant_table
    from sim_core.paper.surface_figures import fig7_surface, fig8_surface, mechanism, table_rows
    from sim_core.paper.values import PAPER
    from sim_core.runs.backends import RunStats

    prog = "insect-gait surface-figures"
    out = Path(args.out)
    doc = None if args.no_doc else Path(args.doc)
    if doc is not None and not doc.is_file():
        print(f"{prog}: error: --doc {doc}: no such file", file=sys.stderr)
        return EXIT_USAGE
    t0 = time.perf_counter()
    stats = RunStats()
    surface = _run(args, prog, stats=stats)
    if surface is None:
        return EXIT_USAGE
    t_fig8 = time.perf_counter() - t0
    paper_args = argparse.Namespace(
        **{**vars(args), "ground": "penalty", "beta": list(MECHANISM_BETAS)}
    )
    paper_ground = _run(paper_args, prog)
    if paper_ground is None:
        return EXIT_USAGE
    # the protocol's own checks on a sample: the pin at a third of its gain, half the step
    cfg = _config(args)
    k3 = argparse.Namespace(
        **{
            **vars(args),
            "beta": list(SAMPLE_BETAS),
            "no_refine": True,
            "d31": None,
            "gain_per_s": cfg.gain_per_s / 3,
        }
    )
    half = argparse.Namespace(**{**vars(k3), "gain_per_s": cfg.gain_per_s})
    sample = {
        "K/3": _run(k3, prog, sample=SAMPLE_D31),
        "dt/2": _run(half, prog, sample=SAMPLE_D31, dt_s=ModelParams().dt / 2),
    }
    if any(v is None for v in sample.values()):
        return EXIT_USAGE
    checks, checks_ok = variant_rows(surface, {k: v for k, v in sample.items() if v}, cfg.floor_rad)
    wall = time.perf_counter() - t0
    out.mkdir(parents=True, exist_ok=True)
    (out / SURFACE_FILE).write_text(surface.model_dump_json())
    (out / "surface_penalty.json").write_text(paper_ground.model_dump_json())
    sweeps = _read_data(out / "fig8.json")
    fig8_surface(surface, out / "fig8_surface.png", PAPER, sweeps)
    maps = (_read_data(out / "fig7.json") or {}).get("maps", [])
    free = {float(m["beta"]): m for m in maps}
    fig7_surface(surface, out / "fig7_surface.png", MAP_BETAS, free)
    mechanism(
        {"constraint": surface, "penalty": paper_ground}, MECHANISM_BETAS, out / "mechanism.png"
    )
    rows = table_rows(surface, PAPER, BETA_TOL)
    lines = ["| paper states | paper | ours (drift surface) | reproduced? |", "|---|---|---|---|"]
    lines += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows]
    lines += [
        "",
        f"Generated by `insect-gait surface-figures`: {len(surface.points)} probes "
        f"({surface.sim_s:.0f} simulated s) for Fig. 8 ({stats.computed} computed, "
        f"{stats.cached} read from the cache) in {t_fig8:.0f} s wall, {wall:.0f} s with the "
        f"paper's ground's mechanism surfaces and the sample checks, on the `{args.backend}` "
        f"backend ({date.today().isoformat()}).",
    ]
    lines += [
        "",
        f"The protocol on a sample (every difference within the {cfg.floor_rad * 1e3:g} "
        f"mrad noise floor: {'yes' if checks_ok else '**no**'}):",
        "",
        variant_table(checks),
    ]
    table = "\n".join(lines)
    if doc is not None:
        doc.write_text(replace_section(doc.read_text(), "surface", table))
    print(table)
    print(describe(surface))
    return 0


def _read_data(path: Path) -> dict[str, Any] | None:
    """The `data` of a reproduce figure file (the free runs Figs. 7-8 are checked against)."""
    try:
        data = json.loads(path.read_text()).get("data")
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _cmd_atlas(args: argparse.Namespace) -> int:
    import time

    from sim_core.model.params import ModelParams
    from sim_core.paper.surface_atlas import draw_atlas, surface_atlas
    from sim_core.runs.backends import RunStats
    from sim_core.runs.cache import ResultCache

    prog = "insect-gait surface-atlas"
    values = args.values or list(ATLAS_VALUES[args.axis])
    field = "body_mass_g" if args.axis == "mass" else "slope_deg"
    cfg = _config(args)
    if not all(_specs_valid(args.beta, cfg, prog, **{field: v}) for v in values):
        return EXIT_USAGE
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
            cache=ResultCache(args.cache),
            backend=backend,
            config=cfg,
            params=ModelParams(ground=args.ground),
            refine=not args.no_refine,
            progress=not args.no_progress,
            stats=stats,
        )
    except KeyboardInterrupt:
        _say_interrupted(prog, args.cache)
        return 130
    finally:
        backend.close()
    wall = time.perf_counter() - t0
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = f"surface_atlas_{args.axis}_{args.ground}"
    (out / f"{stem}.json").write_text(atlas.model_dump_json())
    draw_atlas(atlas, out / f"{stem}.png")
    for v in values:
        row = [p for p in atlas.points if p.value == v]
        cells = ", ".join(f"{p.beta:g}: {p.region}" + (" (?)" if p.unresolved else "") for p in row)
        print(f"{args.axis} {v:g}: {cells}")
    print(
        f"{atlas.sim_s:.0f} simulated s ({stats.computed} probes computed, {stats.cached} "
        f"cached) in {wall:.0f} s wall; wrote {out / stem}.json and .png"
    )
    return 0


def _specs_valid(betas: list[float], cfg: Any, prog: str, **fields: Any) -> bool:
    """Whether every probe's spec is valid (checked before anything runs, in the words the API
    uses: RunSpec's own); if not, says why in one line."""
    from pydantic import ValidationError

    from sim_core.paper.surface import Probe, probe_spec

    try:
        for b in betas:
            for d in (cfg.d31_grid[0], cfg.d31_grid[-1]):
                probe_spec(Probe(b, d, cfg.average_s), cfg, **fields)
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

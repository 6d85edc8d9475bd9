"""`atlas`: the gait atlas from drift surfaces over beta at each body mass or slope (the
viewer's atlas panel), with the surface's grid, pin, run options and model parameters
(sim_core/cli/surface.py).

Its file is named by axis and ground (`surface_atlas_file`: what the viewer reads) for the
defaults; any other model choice or run option adds a tag to the name (`output_tag`), so an
atlas of other parameters never overwrites the defaults' one.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from sim_core.cli.common import EXIT_USAGE, UsageError, out_folder
from sim_core.cli.fields import flag
from sim_core.cli.model import choice_from_args, model_line
from sim_core.cli.paper import backend_from_args, cache_from_args
from sim_core.cli.runflags import output_tag, run_fields, tagged
from sim_core.cli.surface import (
    add_surface_args,
    check_probes,
    say_interrupted,
    surface_config,
)
from sim_core.contract import AXIS_PARAM, ModelChoice
from sim_core.contract.results import RESULTS_DIR, surface_atlas_file

# the atlas from the surface: 13 betas across the paper's window and past it, 0.01 apart
ATLAS_BETAS = tuple(round(0.60 + 0.01 * k, 2) for k in range(13))
# finer near the paper's 3 g and level ground, where the regions change (docs/figures)
ATLAS_VALUES = {
    "mass": (1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 6.0, 8.0),
    "slope": (-20.0, -10.0, -5.0, 0.0, 5.0, 10.0, 20.0),
}


def register(sub: Any) -> None:
    a = sub.add_parser(
        "atlas",
        help="the gait atlas from the drift surface: which gaits are stable over beta x body "
        "mass (or slope), and where their branches fold (the viewer's atlas panel)",
    )
    a.add_argument("--axis", choices=list(AXIS_PARAM), required=True)
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
        + "); the other of --body-mass-g and --slope-deg is held at its flag's value",
    )
    a.add_argument(
        "--out",
        default=str(RESULTS_DIR),
        help="folder for surface_atlas_<axis>_<ground>.json/png (default %(default)s); other "
        "model parameters or run options than the defaults add a tag to the name (the setting "
        "and/or a hash of them), so the defaults' atlas is never overwritten",
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
    a.add_argument(
        "--no-neighbour-walks",
        action="store_true",
        help="do not also walk each cell from the paper's start of every gait a neighbouring "
        "cell holds and it lacks (the surface can miss a narrow pair where it leaves nothing "
        "open; docs/REPRODUCTION.md)",
    )
    add_surface_args(a)
    a.set_defaults(func=_cmd_atlas)


def atlas_path(folder: Path, axis: str, choice: ModelChoice, fields: dict[str, Any]) -> Path:
    """Where the atlas of `choice` and the run fields given goes: the viewer's name for the
    defaults, a tagged one otherwise (`output_tag`)."""
    return tagged(surface_atlas_file(folder, axis, choice.ground), output_tag(fields, choice))


def _cmd_atlas(args: argparse.Namespace) -> int:
    import time
    from dataclasses import replace

    from sim_core.contract.surface import WalkConfig
    from sim_core.contract.template import RunTemplate
    from sim_core.paper.surface_atlas import draw_atlas, surface_atlas
    from sim_core.runs.backends import RunStats

    prog = "insect-gait atlas"
    values = args.values or list(ATLAS_VALUES[args.axis])
    field = AXIS_PARAM[args.axis]  # the RunSpec field the axis varies: --values, not its flag
    choice = choice_from_args(args)
    fields = run_fields(args)
    if field in fields:
        raise UsageError(f"{flag(field)}: an atlas over {args.axis} takes its values from "
                         "--values; give the other axis's flag to hold it elsewhere")  # fmt: skip
    cfg = replace(surface_config(args), band_pass=args.band_pass)
    for v in values:
        check_probes(args.beta, cfg, fields | {field: v})
    js = atlas_path(out_folder(args.out, "--out"), args.axis, choice, fields)
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
            params=choice.model_params(),
            template=RunTemplate.model_validate(fields),
            refine=not args.no_refine,
            walks=None if args.no_walks else WalkConfig(),
            neighbour_walks=not args.no_neighbour_walks,
            progress=not args.no_progress,
            stats=stats,
        )
    except KeyboardInterrupt:
        say_interrupted(prog, args.cache)
        return 130
    finally:
        backend.close()
    wall = time.perf_counter() - t0
    atlas = atlas.model_copy(update={"setting": choice.setting})
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
    if model_line(choice):
        print(model_line(choice))
    return 0

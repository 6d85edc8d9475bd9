"""`insect-gait viewer`: plugged into the core's command line through an entry point.

sim_core discovers `register` at run time (pyproject `insect_gait.commands`), so the core never
imports the web package; viser (and MuJoCo) are imported only when the command runs, so that
`insect-gait --help` and `insect-gait run` never pay for them.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
from pathlib import Path

from sim_core.cli import EXIT_USAGE, add_model_args, choice_from_args, port_number, port_taken
from sim_core.contract import RESULTS_ENV
from web.frame_cap import MIN_FPS, SOFTWARE_FPS
from web.paths import DEFAULT_API_URL, DEFAULT_BIFURCATION, SURFACE_FILE


def register(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser(
        "viewer",
        help="live 3D viewer in the browser (viser): sliders for beta, mass, slope",
        description="Serve the walking hexapod at http://HOST:PORT with live controls and plots.",
    )
    p.add_argument(
        "--host", default="127.0.0.1", help="interface to listen on (default %(default)s)"
    )
    p.add_argument(
        "--port", type=port_number, default=8080, help="port, 1..65535 (default %(default)s)"
    )
    p.add_argument(
        "--bifurcation",
        type=Path,
        default=DEFAULT_BIFURCATION,
        help="the finder's results (a FinderOutput, `insect-gait finder`) to draw, if "
        "present; atlas_mass.json and atlas_slope.json are read from the same folder "
        f"(default %(default)s; {RESULTS_ENV} sets the folder)",
    )
    p.add_argument(
        "--surface",
        type=Path,
        default=None,
        help="the drift surface (a DriftSurface, `insect-gait reproduce`) to draw, if "
        f"present (default: {SURFACE_FILE} next to the bifurcation file)",
    )
    p.add_argument(
        "--api-url",
        default=DEFAULT_API_URL,
        help="the REST API the 'Submit as a job' panel posts to (default %(default)s)",
    )
    p.add_argument(
        "--shadows",
        action="store_true",
        help="cast shadows in the 3D view (extra render passes every frame: off by default, "
        "as a browser without a GPU pays them on the simulation's cores)",
    )
    p.add_argument(
        "--software-fps",
        type=frames_a_second,
        default=SOFTWARE_FPS,
        help="frames a second a browser without a GPU draws the 3D view at (it draws WebGL on "
        "the CPU the simulation needs; 0: every frame; a browser's own ?frameCap=N overrides "
        "it; default %(default)g)",
    )
    add_model_args(p)  # --ground, --setting, --param NAME=VALUE: as `insect-gait run`'s
    p.set_defaults(func=run)


def frames_a_second(text: str) -> float:
    """argparse type for a frame cap: 0 (every frame) or at least MIN_FPS, said in one line."""
    try:
        fps = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of frames a second") from None
    if not (math.isfinite(fps) and (fps == 0 or fps >= MIN_FPS)):
        raise argparse.ArgumentTypeError(
            f"{fps:g} frames a second: give 0 (every frame) or at least {MIN_FPS:g}"
        )
    return fps


def _refuse_busy(args: argparse.Namespace) -> int:
    print(
        f"insect-gait viewer: port {args.port} on {args.host} is already in use (another "
        "viewer?); stop that one or choose another with --port (make run VIEWER_PORT=...)",
        file=sys.stderr,
        flush=True,
    )
    return EXIT_USAGE


def run(args: argparse.Namespace) -> int:
    # viser moves on to the next free port by itself; a URL printed before it started (make
    # run's) would then name somebody else's server: refuse instead, before building anything
    model = choice_from_args(args)  # refused in one line before anything starts
    if port_taken(args.host, args.port):
        return _refuse_busy(args)
    from web.app import LoopConfig, ViewerApp

    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    surface = args.surface or args.bifurcation.parent / SURFACE_FILE
    app = ViewerApp(
        args.host,
        args.port,
        bifurcation_path=args.bifurcation,
        surface_path=surface,
        api_url=args.api_url,
        model=model,
        config=LoopConfig(shadows=args.shadows, software_fps=args.software_fps),
    )
    if app.port != args.port:  # taken in the instant between the check and viser's bind
        app.server.stop()
        return _refuse_busy(args)
    print(f"viewer: http://{args.host}:{app.port}", flush=True)
    app.serve_forever()
    return 0

"""`insect-gait viewer`: plugged into the core's command line through an entry point.

sim_core discovers `register` at run time (pyproject `insect_gait.commands`), so the core never
imports the web package; viser is only imported when the command actually runs.
"""

from __future__ import annotations

import argparse
import logging
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    from web.app import DEFAULT_BIFURCATION

    p = subparsers.add_parser(
        "viewer",
        help="live 3D viewer in the browser (viser): sliders for beta, mass, slope",
        description="Serve the walking hexapod at http://HOST:PORT with live controls and plots.",
    )
    p.add_argument(
        "--host", default="127.0.0.1", help="interface to listen on (default %(default)s)"
    )
    p.add_argument("--port", type=int, default=8080, help="port (default %(default)s)")
    p.add_argument(
        "--bifurcation",
        type=Path,
        default=DEFAULT_BIFURCATION,
        help="cached bifurcation results to draw, if present (default %(default)s)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from web.app import ViewerApp

    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    app = ViewerApp(args.host, args.port, bifurcation_path=args.bifurcation)
    # viser moves to the next free port if this one is taken: print the real address
    print(f"viewer: http://{args.host}:{app.port}", flush=True)
    app.serve_forever()
    return 0

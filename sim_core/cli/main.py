"""`insect-gait` command line: a thin layer over the public API.

Subcommands of packages that sim_core must not import (the REST service, the viewer) arrive
through the entry-point group `insect_gait.commands`; each entry point is a
`register(subparsers)` function.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from importlib.metadata import entry_points

from sim_core.cli import numerics, paper, surface, walk
from sim_core.cli.common import EXIT_USAGE, Parser

__all__ = ["EXIT_USAGE", "build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="insect-gait",
        description=__doc__.splitlines()[0] if __doc__ else "",
        epilog="The studies behind docs/REPRODUCTION.md (calibration, sensitivity, the "
        "finder's checks, the campaigns' screens) are `python -m lab --help`.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for family in (walk, numerics, paper, surface):
        family.register(sub)
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

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

from pydantic import ValidationError

from sim_core.cli import atlas, cache, numerics, paper, surface, walk
from sim_core.cli.common import (
    EXIT_USAGE,
    TRACEBACK_ENV,
    Parser,
    UsageError,
    one_line,
    traceback_wanted,
)

__all__ = ["EXIT_USAGE", "build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="insect-gait",
        description=__doc__.splitlines()[0] if __doc__ else "",
        epilog="The studies behind docs/REPRODUCTION.md (calibration, sensitivity, the "
        "finder's checks, the campaigns' screens) are `python -m lab --help`. Errors are "
        f"one line; {TRACEBACK_ENV}=1 shows a traceback instead.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for family in (walk, numerics, paper, surface, atlas, cache):
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
    """Run one command; every error it meets ends as one line on stderr, never a traceback:
    argparse's and a command's own refusals (UsageError, exit 2), and, as the net under
    them, a model's validation error or a file error from inside a command (exit 1)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    func = getattr(args, "func", None)
    if func is None:
        parser.error(f"command {args.command!r} is not available")
    prog = f"{parser.prog} {args.command}"
    try:
        return int(func(args))
    except UsageError as exc:
        code, words = EXIT_USAGE, str(exc)
    except (ValidationError, OSError) as exc:
        if traceback_wanted():
            raise
        code, words = 1, one_line(exc)
    print(f"{prog}: error: {words}", file=sys.stderr)
    return code


if __name__ == "__main__":
    sys.exit(main())

"""`python -m lab`: the studies behind docs/REPRODUCTION.md, outside the product.

The product's `insect-gait` lists walking, the paper's figures and the service; the
calibration, sensitivity, the finder's checks and the campaigns' screens live here, in a folder
the package does not install (run from a checkout: `.venv/bin/python -m lab --help`).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from lab import commands, paper_commands
from sim_core.cli import Parser

PROG = "python -m lab"


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog=PROG, description=__doc__.splitlines()[0] if __doc__ else "")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    paper_commands.register(sub)
    commands.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return int(args.func(args))


if __name__ == "__main__":
    sys.exit(main())

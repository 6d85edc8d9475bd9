"""`insect-gait-lab` command line: the studies behind docs/REPRODUCTION.md, kept apart from the
product's `insect-gait` (a user's --help lists walking, the paper's figures and the service;
the calibration, sensitivity, the finder's checks and the campaigns' screens live here)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from sim_core.cli import paper, studies
from sim_core.cli.common import Parser


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="insect-gait-lab", description=__doc__.splitlines()[0] if __doc__ else "")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    paper.register_lab(sub)
    studies.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return int(args.func(args))


if __name__ == "__main__":
    sys.exit(main())

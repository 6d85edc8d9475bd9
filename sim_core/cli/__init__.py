"""The `insect-gait` command line."""

from sim_core.cli.main import build_parser, main

__all__ = ["build_parser", "main"]

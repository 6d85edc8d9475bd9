"""The `insect-gait` command line. Plug-ins (the REST service, the viewer) may use
`port_number`, `port_taken` and `EXIT_USAGE`, so that every command checks and words its
arguments alike."""

from sim_core.cli.common import EXIT_USAGE, port_number, port_taken
from sim_core.cli.main import build_parser, main

__all__ = ["EXIT_USAGE", "build_parser", "main", "port_number", "port_taken"]

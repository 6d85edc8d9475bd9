"""The `insect-gait` command line. Plug-ins (the REST service, the viewer) and the lab's
`python -m lab` may use its helpers, so that every command checks and words its arguments
alike: `port_number`, `port_taken`, `EXIT_USAGE`; `Parser` (one-line errors, exit 2); `UsageError`
(raise it from a command: `main` prints its words in one line and exits 2);
`add_backend_args` / `backend_from_args` (--cache, --backend, --address, --workers: where runs
go and where they are kept); and `add_model_args` / `choice_from_args` (--ground, --setting,
--param NAME=VALUE: the model's parameters, as the contract's `ModelChoice`)."""

from sim_core.cli.common import EXIT_USAGE, Parser, UsageError, port_number, port_taken
from sim_core.cli.main import build_parser, main
from sim_core.cli.model import add_model_args, choice_from_args
from sim_core.cli.paper import add_backend_args, backend_from_args

__all__ = [
    "EXIT_USAGE",
    "Parser",
    "UsageError",
    "add_backend_args",
    "add_model_args",
    "backend_from_args",
    "build_parser",
    "choice_from_args",
    "main",
    "port_number",
    "port_taken",
]

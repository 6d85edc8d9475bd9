"""`insect-gait api`: the command-line plug-in (see docs/CORE_API.md for the contract).

Flags override the environment (INSECT_GAIT_*), which overrides the defaults in Settings.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any


def register(subparsers: Any) -> argparse.ArgumentParser:
    """Add the `api` subcommand to the `insect-gait` parser."""
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "api",
        help="run the REST service (jobs queue, worker processes, SQLite store)",
        description="Run the insect-gait REST API. Settings come from INSECT_GAIT_* environment "
        "variables; these flags override them. OpenAPI docs at http://HOST:PORT/docs.",
    )
    add_arguments(parser)
    parser.set_defaults(func=run_api)
    return parser


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--host", help="interface to bind (default 127.0.0.1)")
    parser.add_argument("--port", type=int, help="TCP port (default 8000)")
    parser.add_argument("--db", type=Path, help="SQLite database path")
    parser.add_argument(
        "--workers", type=int, help="worker processes (default: cores - 1, at least 1)"
    )


def settings_from_args(args: argparse.Namespace) -> Any:
    from server.settings import Settings

    overrides = {
        "host": args.host,
        "port": args.port,
        "db_path": args.db,
        "workers": args.workers,
    }
    return Settings(**{k: v for k, v in overrides.items() if v is not None})


def run_api(args: argparse.Namespace) -> int:
    """Serve until interrupted; returns the exit code."""
    import uvicorn
    from pydantic import ValidationError

    from server.app import create_app

    try:
        settings = settings_from_args(args)
    except ValidationError as exc:
        print(f"insect-gait api: invalid settings:\n{exc}")
        return 2
    app = create_app(settings)
    print(
        f"insect-gait api: http://{settings.host}:{settings.port}/docs "
        f"(db {settings.db_path}, {settings.workers} workers)",
        flush=True,
    )
    # One process on purpose: the worker pool and the instance lock belong to this process.
    uvicorn.run(app, host=settings.host, port=settings.port, log_level=settings.log_level)
    return 0


def main(argv: list[str] | None = None) -> int:
    """`python -m server`: the same command without the sim_core CLI in front."""
    parser = argparse.ArgumentParser(prog="python -m server")
    add_arguments(parser)
    args = parser.parse_args(argv)
    return run_api(args)

"""`insect-gait api`: the command-line plug-in (see docs/CORE_API.md for the contract).

Flags override the environment (INSECT_GAIT_*), which overrides the defaults in Settings.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path
from typing import Any

from sim_core.cli import port_number, port_taken


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
    parser.add_argument("--port", type=port_number, help="TCP port, 1..65535 (default 8000)")
    parser.add_argument("--db", type=Path, help="SQLite database path")
    parser.add_argument(
        "--workers", type=int, help="worker processes (default: cores - 1, at least 1)"
    )
    parser.add_argument(
        "--cache", type=Path,
        help="result cache folder, shared with the CLI (default: INSECT_GAIT_CACHE_DIR, else "
        "the installation's; `insect-gait cache info`)",
    )  # fmt: skip
    parser.add_argument(
        "--dask-address",
        help="a dask.distributed scheduler (tcp://host:8786) to run the jobs' simulations on "
        "(default: INSECT_GAIT_DASK_ADDRESS, else the workers compute them)",
    )


def settings_from_args(args: argparse.Namespace) -> Any:
    from server.settings import Settings

    overrides = {
        "host": args.host,
        "port": args.port,
        "db_path": args.db,
        "workers": args.workers,
        "cache_dir": getattr(args, "cache", None),
        "dask_address": getattr(args, "dask_address", None),
    }
    return Settings(**{k: v for k, v in overrides.items() if v is not None})


def run_api(args: argparse.Namespace) -> int:
    """Serve until interrupted; returns the exit code."""
    import uvicorn
    from pydantic import ValidationError

    from server.app import InstanceLock, create_app

    try:
        settings = settings_from_args(args)
    except ValidationError as exc:
        print(f"insect-gait api: invalid settings: {settings_problem(exc)}", file=sys.stderr)
        return 2
    if settings.dask_address and importlib.util.find_spec("distributed") is None:
        print(
            f"insect-gait api: --dask-address {settings.dask_address} needs dask.distributed "
            "(pip install 'insect-gait[cluster]'; the image: build with INSTALL_EXTRAS=cluster)",
            file=sys.stderr,
        )
        return 1
    if settings.port and port_taken(settings.host, settings.port):
        print(
            f"insect-gait api: port {settings.port} on {settings.host} is already in use "
            "(another api?); stop that one or choose another with --port",
            file=sys.stderr,
        )
        return 1
    try:  # before uvicorn, whose failed startup would print its traceback first
        settings.db_path.parent.mkdir(parents=True, exist_ok=True)
        InstanceLock(str(settings.db_path)).probe()
    except (RuntimeError, OSError) as exc:
        print(f"insect-gait api: {exc}", file=sys.stderr)
        return 1
    app = create_app(settings)
    print(banner(settings), flush=True)
    # One process on purpose: the worker pool and the instance lock belong to this process.
    uvicorn.run(app, host=settings.host, port=settings.port, log_level=settings.log_level)
    return 0


def banner(settings: Any) -> str:
    """The line the server prints when it starts: where its docs are, its database, workers."""
    n = settings.workers
    where = f", on the Dask cluster at {settings.dask_address}" if settings.dask_address else ""
    return (
        f"insect-gait api: http://{settings.host}:{settings.port}/docs "
        f"(db {settings.db_path}, result cache {settings.cache_dir}, "
        f"{n} worker{'' if n == 1 else 's'}{where})"
    )


def settings_problem(exc: Any) -> str:
    """A settings ValidationError in one line, naming the flag and the environment variable
    that can set each field (pydantic's own text ends in a library URL)."""
    flags = {"host": "--host", "port": "--port", "db_path": "--db", "workers": "--workers",
             "cache_dir": "--cache", "dask_address": "--dask-address"}  # fmt: skip
    parts = []
    for err in exc.errors():
        name = ".".join(str(x) for x in err["loc"]) or "settings"
        by = f"{flags[name]} or " if name in flags else ""  # the others have no flag
        parts.append(f"{name} ({by}INSECT_GAIT_{name.upper()}): {err['msg']}")
    return "; ".join(parts)


def main(argv: list[str] | None = None) -> int:
    """`python -m server`: the same command without the sim_core CLI in front."""
    parser = argparse.ArgumentParser(prog="python -m server")
    add_arguments(parser)
    args = parser.parse_args(argv)
    return run_api(args)

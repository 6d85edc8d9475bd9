"""What every command family shares: the one-line argparse error, exit codes, and which
markdown file a generating command rewrites."""

from __future__ import annotations

import argparse
import socket
from pathlib import Path

EXIT_USAGE = 2


def port_number(text: str) -> int:
    """argparse type for a TCP port: 1..65535, said in one line (0 would pick a random port,
    which a printed URL could not name)."""
    try:
        port = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a port number (1..65535)") from None
    if not 1 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"{port} is not a port number (1..65535)")
    return port


def port_taken(host: str, port: int) -> bool:
    """True when a server already listens on (host, port): a bind test, as a server's own
    (SO_REUSEADDR, so a port in TIME_WAIT counts as free)."""
    try:
        family, kind, proto, _, addr = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0]
    except OSError:
        return False  # an unknown host: let the server say so
    with socket.socket(family, kind, proto) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind(addr)
        except OSError:
            return True
    return False


class Parser(argparse.ArgumentParser):
    """argparse that reports errors in one line and exits 2 (never a traceback)."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\n")


def doc_to_update(args: argparse.Namespace, default: str) -> Path | None:
    """The markdown file a generating command rewrites its section of: --doc, else `default`
    for a full run; none with --no-doc, or with --quick unless --doc names one."""
    if args.no_doc or not (args.doc or not args.quick):
        return None
    doc = Path(args.doc or default)
    if not doc.is_file():
        raise FileNotFoundError(f"--doc {doc}: no such file")
    return doc

"""What every command family shares: the one-line error (argparse's, a refusal's, an
exception's), exit codes, and the files a command reads or writes, checked before it runs."""

from __future__ import annotations

import argparse
import os
import socket
from pathlib import Path

from pydantic import ValidationError

EXIT_USAGE = 2
# set to 1 to let an error that `main` would print in one line raise with its traceback
TRACEBACK_ENV = "INSECT_GAIT_TRACEBACK"


class UsageError(Exception):
    """A refusal of what the person typed (a flag's value, a file it names): `main` prints
    its words in one line, after the command's name, and exits EXIT_USAGE."""


def one_line(exc: BaseException) -> str:
    """An exception in the one line a command prints: each refused field of a pydantic model
    with its words, a file error as "path: reason", anything else its message, whitespace
    folded (a multi-line message would read as a traceback's tail)."""
    if isinstance(exc, ValidationError):
        parts = []
        for err in exc.errors():
            where = ".".join(str(x) for x in err["loc"])
            msg = str(err["msg"]).removeprefix("Value error, ")
            parts.append(f"{where}: {msg}" if where else msg)
        return "; ".join(parts)
    if isinstance(exc, OSError) and exc.strerror:
        return f"{exc.filename}: {exc.strerror}" if exc.filename is not None else exc.strerror
    return " ".join(str(exc).split()) or type(exc).__name__


def traceback_wanted() -> bool:
    """Whether TRACEBACK_ENV asks for tracebacks instead of one-line errors (a developer's
    switch: what failed where, in code that should not have failed)."""
    return os.environ.get(TRACEBACK_ENV, "") not in ("", "0")


def out_file(text: str | None, flag: str) -> Path | None:
    """A file a command will write when it is done, checked before it runs: its folder must
    exist and be writable (a missing folder found after a long computation loses it)."""
    if text is None:
        return None
    path = Path(text)
    folder = path.parent
    if path.is_dir():
        raise UsageError(f"{flag} {path}: is a folder; name a file")
    if not folder.is_dir():
        raise UsageError(f"{flag} {path}: no folder {folder}; create it first")
    if not os.access(folder, os.W_OK):
        raise UsageError(f"{flag} {path}: the folder {folder} is not writable")
    return path


def out_folder(text: str | Path, flag: str) -> Path:
    """A folder a command writes into, made (with its parents) before it runs: one that
    cannot be made is refused now, not after the computation."""
    path = Path(text)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"{flag} {path}: {exc.strerror or exc}") from None
    if not os.access(path, os.W_OK):
        raise UsageError(f"{flag} {path}: not writable")
    return path


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


def doc_to_update(args: argparse.Namespace, default: str, section: str) -> Path | None:
    """The markdown file a generating command rewrites its `section` of: --doc, else `default`
    for a full run; none with --no-doc, or with --quick unless --doc names one. Checked before
    the command runs (it exists, is readable and has the section's markers): a UsageError
    otherwise, which says what to do."""
    if args.no_doc or not (args.doc or not args.quick):
        return None
    doc = Path(args.doc or default)
    if not doc.is_file():
        if args.doc:
            raise UsageError(f"--doc {doc}: no such file")
        raise UsageError(f"{doc} (the default --doc) is not here: run from the project's "
                         "folder, or pass --doc FILE or --no-doc")  # fmt: skip
    return _with_section(doc, section, "--doc")


def _with_section(doc: Path, section: str, flag: str) -> Path:
    """`doc` if it holds `section`'s begin and end markers, in order; else a UsageError."""
    from sim_core.docsections import markers

    begin, end = markers(section)
    try:
        text = doc.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise UsageError(f"{flag} {doc}: {one_line(exc)}") from None
    if begin not in text or end not in text.split(begin, 1)[1]:
        raise UsageError(f"{flag} {doc}: no {begin} ... {end} section to rewrite; put those "
                         "two lines where the generated text goes")  # fmt: skip
    return doc


def doc_with_section(text: str, section: str, flag: str) -> Path:
    """A markdown file a command rewrites `section` of, named by `flag`: it must exist and
    hold the section's markers (checked before anything is computed)."""
    doc = Path(text)
    if not doc.is_file():
        what = "is a folder" if doc.is_dir() else "no such file"
        raise UsageError(f"{flag} {doc}: {what}")
    return _with_section(doc, section, flag)

"""The one place the viewer reaches into viser 1.1's private message channel.

viser 1.1 has no public way to hear every control's update (web/entry.py needs it: a typed
value applies when another control is used) or to run a script in every page (web/frame_cap.py:
the 3D view's frame cap); both go through the server's websocket interface and its message
classes, which is why pyproject pins viser to 1.1. A viser without them raises `NoHook`, and
each caller falls back to what works without it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # web/cli.py reaches this through frame_cap: `--help` must not load viser
    import viser


class NoHook(RuntimeError):
    """This viser has no such private hook."""


def private_channel(server: viser.ViserServer, *messages: str) -> tuple[Any, tuple[Any, ...]]:
    """The server's websocket interface and the named message classes of `viser._messages`."""
    try:
        from viser import _messages

        interface: Any = server.gui._websock_interface
        return interface, tuple(getattr(_messages, name) for name in messages)
    except (ImportError, AttributeError) as exc:
        raise NoHook(str(exc)) from exc

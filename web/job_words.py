"""The job panel's words: a job's state and what went wrong, as a person reads them.

A state is the API's own (queued, running, done, failed, cancelled) or one of the viewer's for
a call that got no job back, each named for what happened: "unreachable" (nothing answers at
the API's address), "not found" (the API has no such job: HTTP 404), "refused" (the API said
no: a body it does not take, a full queue, a missing token) and "API error" (it answered, but
not with a job). The message says it in words with the API's own detail, never a Python
exception's name.
"""

from __future__ import annotations

import base64
import html
import json
import socket
import urllib.error
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from web.jobs import JobView

TERMINAL = ("done", "failed", "cancelled")  # the API's finished states
NO_JOB = ("unreachable", "not found", "refused", "API error")  # the viewer's: no job came back
PROBLEM = ("failed", *NO_JOB)  # said in red
START_API = "start it (`make run`, or `insect-gait api`) or put its address in 'API URL'"


def _detail(exc: urllib.error.HTTPError) -> str:
    """The API's `detail`: a sentence, or FastAPI's list of field problems ("beta: ...")."""
    try:
        detail = json.loads(exc.read()).get("detail")
    except (ValueError, AttributeError, OSError):
        detail = None
    if isinstance(detail, list):
        parts = []
        for d in detail:
            if isinstance(d, dict):
                loc = ".".join(str(x) for x in d.get("loc", ())[1:])
                parts.append(f"{loc}: {d.get('msg', '')}" if loc else str(d.get("msg", "")))
            else:
                parts.append(str(d))
        return "; ".join(parts)
    return str(detail) if detail is not None else str(exc.reason)


def problem(exc: BaseException, api: str) -> tuple[str, str]:
    """(state, message) for a call to the API at `api` that raised `exc`."""
    if isinstance(exc, urllib.error.HTTPError):
        detail = _detail(exc)
        if exc.code == 404:
            return "not found", f"the API has no such job (HTTP 404: {detail})"
        if exc.code < 500:
            return "refused", f"the API refused it (HTTP {exc.code}): {detail}"
        return "API error", f"the API failed (HTTP {exc.code}): {detail}"
    if isinstance(exc, urllib.error.URLError) or isinstance(exc, OSError):
        reason = getattr(exc, "reason", exc)
        if isinstance(reason, (TimeoutError, socket.timeout)):
            return "unreachable", f"no answer from the API at {api} in time; {START_API}"
        words = getattr(reason, "strerror", None) or str(reason)
        return "unreachable", f"no API answers at {api} ({str(words).lower()}); {START_API}"
    return "API error", f"the API at {api} did not answer with a job ({exc})"


def state_words(view: JobView) -> str:
    """The state and, while it runs, how far it is and the API's estimate of the time left."""
    if view.status == "running":
        eta = "" if view.eta_s is None else f", about {view.eta_s:.0f} s left"
        return f"running {100 * view.progress:.0f}%{eta}"
    return view.status


def _ident(view: JobView) -> str:
    """The job's id, a link to its JSON once the API gave one."""
    if not view.url:
        return html.escape(view.id)
    return f'<a href="{html.escape(view.url)}" target="_blank">{html.escape(view.id)}</a>'


def job_status_html(view: JobView) -> str:
    """The newest job in one line: kind, id (a link to its JSON), state, progress, message,
    and its figure once it is done."""
    if view.status == "none":
        return "<em>no job submitted from this viewer yet</em>"
    msg = f" — {html.escape(view.message)}" if view.message else ""
    colour = "#b00" if view.status in PROBLEM else "#222"
    figure = ""
    if view.figure_png:
        data = base64.b64encode(view.figure_png).decode()
        figure = (
            f'<img data-job-figure alt="the figure of job {html.escape(view.id)}" '
            f'style="width:100%;margin-top:3px" src="data:image/png;base64,{data}"/>'
        )
    return (
        f'<div data-job-status="{html.escape(view.status)}" style="font-size:0.85em;'
        f'color:{colour};overflow-wrap:anywhere">{html.escape(view.kind)} job {_ident(view)}: '
        f"<b>{html.escape(state_words(view))}</b>{msg}{figure}</div>"
    )


def job_row_html(view: JobView, replaying: bool) -> str:
    """One row of the job list: kind, short id (linked), state in words, the API's note."""
    msg = f" — {html.escape(view.message)}" if view.message else ""
    colour = "#b00" if view.status in PROBLEM else "#222"
    shown = " · <b>replayed in the panels</b>" if replaying else ""
    short = view.id[:8] or "…"
    link = (
        f'<a href="{html.escape(view.url)}" target="_blank">{html.escape(short)}</a>'
        if view.url
        else html.escape(short)
    )
    return (
        f'<div data-job-row="{view.key}" data-job-id="{html.escape(view.id)}" '
        f'data-state="{html.escape(view.status)}" style="font-size:0.8em;color:{colour};'
        f'overflow-wrap:anywhere">{html.escape(view.kind)} {link}: '
        f"<b>{html.escape(state_words(view))}</b>{msg}{shown}</div>"
    )


def jobs_summary(views: Sequence[Any]) -> str:
    """The list's heading: how many jobs and how many still run."""
    if not views:
        return "<em>jobs from this viewer: none yet</em>"
    busy = sum(1 for v in views if not v.finished)
    return (
        f'<div data-jobs="{len(views)}" style="font-size:0.8em"><b>jobs from this viewer</b>: '
        f"{len(views)}, {busy} not finished (newest first)</div>"
    )

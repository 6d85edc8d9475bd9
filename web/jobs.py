"""The viewer as a client of the service: submit the current settings as a job, follow it, and
bring back its figure; or open a job that already exists by its id.

HTTP never runs on the loop thread (a slow or absent API must not stop the walk): each job is
followed by one daemon thread that replaces `JobWatcher.view`, a frozen snapshot the loop reads
when it redraws the panel. Plain `urllib` and the API's JSON (docs/API.md): the viewer speaks
to the service the way any client does, never through the server's code.
"""

from __future__ import annotations

import base64
import html
import json
import threading
import time
import urllib.error
import urllib.request
from dataclasses import dataclass, replace
from typing import Any

TERMINAL = ("done", "failed", "cancelled")  # the API's finished states


@dataclass(frozen=True)
class JobView:
    """What the panel shows of the job being followed."""

    id: str = ""
    kind: str = ""
    status: str = "none"  # "none", "submitting", then the API's states, or "unreachable"
    progress: float = 0.0
    message: str = ""  # the API's error or note, or why the API could not be reached
    figure_png: bytes | None = None  # the job's figure once it is done
    url: str = ""  # the job's own address
    # a done run job's first run, (time_s, Delta31) at each leg-1 touchdown, when the job kept
    # its series (the viewer's own run jobs do): drawn on the Delta31 history
    d31_series: tuple[tuple[float, float], ...] = ()

    @property
    def finished(self) -> bool:
        return self.status in TERMINAL or self.status == "unreachable"


def _request(url: str, body: dict[str, Any] | None, timeout_s: float) -> bytes:
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(
        url,
        data=data,
        headers={"Content-Type": "application/json"} if data else {},
        method="POST" if data else "GET",
    )
    with urllib.request.urlopen(req, timeout=timeout_s) as response:
        return bytes(response.read())


def _why(exc: Exception) -> str:
    """An HTTP error's own detail (the API says what was wrong), else the reason in one line."""
    if isinstance(exc, urllib.error.HTTPError):
        try:
            detail = json.loads(exc.read()).get("detail")
        except (ValueError, AttributeError):
            detail = None
        return f"HTTP {exc.code}: {detail if detail is not None else exc.reason}"
    reason = getattr(exc, "reason", None) or exc
    return f"{type(exc).__name__}: {reason}"


class JobWatcher:
    """Follows one job at a time; a new submit or open replaces the one followed."""

    def __init__(self, poll_s: float = 1.0, timeout_s: float = 10.0) -> None:
        self.poll_s = poll_s
        self.timeout_s = timeout_s
        self.view = JobView()
        self._generation = 0
        self._lock = threading.Lock()

    def submit(self, api_url: str, body: dict[str, Any]) -> None:
        """POST `body` to the API's jobs and follow the job it makes."""
        self._start(api_url, body, None)

    def open(self, api_url: str, job_id: str) -> None:
        """Follow an existing job (any kind) by its id: its progress, then its figure."""
        self._start(api_url, None, job_id.strip())

    def _start(self, api_url: str, body: dict[str, Any] | None, job_id: str | None) -> None:
        with self._lock:
            self._generation += 1
            generation = self._generation
        kind = str(body.get("kind", "")) if body else ""
        self._set(generation, JobView(id=job_id or "", kind=kind, status="submitting"))
        threading.Thread(
            target=self._follow,
            args=(generation, api_url.rstrip("/"), body, job_id),
            name="job-watcher",
            daemon=True,
        ).start()

    def _set(self, generation: int, view: JobView) -> bool:
        """Publish `view` unless a newer job replaced this one; False: stop following."""
        with self._lock:
            if generation != self._generation:
                return False
            self.view = view
            return True

    def _follow(
        self, generation: int, api: str, body: dict[str, Any] | None, job_id: str | None
    ) -> None:
        view = self.view
        try:
            if body is not None:
                job = json.loads(_request(f"{api}/v1/jobs", body, self.timeout_s))
            else:
                job = json.loads(_request(f"{api}/v1/jobs/{job_id}", None, self.timeout_s))
            while True:
                view = JobView(
                    id=job["id"],
                    kind=job["kind"],
                    status=job["status"],
                    progress=float(job.get("progress") or 0.0),
                    message=job.get("error") or job.get("note") or "",
                    url=f"{api}/v1/jobs/{job['id']}",
                )
                if not self._set(generation, view):
                    return
                if job["status"] in TERMINAL:
                    break
                time.sleep(self.poll_s)
                job = json.loads(_request(view.url, None, self.timeout_s))
            if job["status"] == "done":
                png = _request(f"{view.url}/figure.png", None, 60.0)
                result = json.loads(_request(f"{view.url}/result", None, 60.0))
                self._set(generation, replace(view, figure_png=png,
                                              d31_series=first_run_d31(result)))  # fmt: skip
        except Exception as exc:  # the API absent, refusing, or answering nonsense
            self._set(generation, replace(view, status="unreachable", message=_why(exc)))


def first_run_d31(result: dict[str, Any]) -> tuple[tuple[float, float], ...]:
    """(time_s, Delta31) of a run job's first run from its stored result (`GET .../result`),
    or () when the job kept no series or is of another kind."""
    rows = result.get("result", {}).get("series", {}).get("d31", [])
    return tuple((float(r["time_s"]), float(r["d31"])) for r in rows if r.get("run") == 0)


def job_status_html(view: JobView) -> str:
    """The followed job in one line: kind, id (a link to its JSON), state, progress, message."""
    if view.status == "none":
        return "<em>no job submitted from this viewer yet</em>"
    ident = (
        f'<a href="{html.escape(view.url)}" target="_blank">{html.escape(view.id)}</a>'
        if view.url
        else html.escape(view.id)
    )
    pct = f" {100 * view.progress:.0f}%" if view.status == "running" else ""
    msg = f" — {html.escape(view.message)}" if view.message else ""
    colour = "#b00" if view.status in ("failed", "unreachable") else "#222"
    figure = ""
    if view.figure_png:
        data = base64.b64encode(view.figure_png).decode()
        figure = (
            f'<img data-job-figure alt="the figure of job {html.escape(view.id)}" '
            f'style="width:100%;margin-top:3px" src="data:image/png;base64,{data}"/>'
        )
    return (
        f'<div data-job-status="{html.escape(view.status)}" style="font-size:0.85em;'
        f'color:{colour};overflow-wrap:anywhere">{html.escape(view.kind)} job {ident}: '
        f"<b>{html.escape(view.status)}</b>{pct}{msg}{figure}</div>"
    )

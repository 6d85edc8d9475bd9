"""The viewer as a client of the service: the jobs it submitted or opened, each followed to its
end, cancelled on request, its figure and (for a run or a hysteresis job) its run brought back
to replay in the panels.

HTTP never runs on the loop thread (a slow or absent API must not stop the walk): each job is
followed by one daemon thread that replaces its `JobView`, a frozen snapshot the loop reads
when it redraws the panel. Plain `urllib` and the API's JSON (docs/API.md): the viewer speaks
to the service the way any client does, never through the server's code. The list keeps the
latest `KEEP` jobs; a job dropped from it is no longer followed (the API still has it).
"""

from __future__ import annotations

import json
import threading
import time
import urllib.request
from dataclasses import dataclass, field, replace
from typing import Any

from web.job_replay import REPLAYABLE, Replay, first_run_d31, replay_of
from web.job_words import NO_JOB, TERMINAL, job_status_html, problem

__all__ = ["TERMINAL", "JobView", "JobWatcher", "api_failure", "api_json", "job_status_html"]
KEEP = 8  # jobs listed: a panel of rows, not a history (the API lists them all)


@dataclass(frozen=True)
class JobView:
    """What the panel shows of one job."""

    id: str = ""
    kind: str = ""
    status: str = "none"  # "none", "submitting", then the API's states, or one of NO_JOB
    progress: float = 0.0
    message: str = ""  # the API's error or note, or why the API gave no job back
    figure_png: bytes | None = None  # the job's figure once it is done
    url: str = ""  # the job's own address
    # a done run job's first run, (time_s, Delta31) at each leg-1 touchdown, when the job kept
    # its series (the viewer's own run jobs do): drawn on the Delta31 history
    d31_series: tuple[tuple[float, float], ...] = ()
    key: int = 0  # the list's own number for it (a job has no id until the API answers)
    eta_s: float | None = None  # the API's estimate of the time left while it runs
    replay: Replay | None = field(default=None, compare=False, repr=False)

    @property
    def finished(self) -> bool:
        return self.status in TERMINAL or self.status in NO_JOB

    @property
    def cancellable(self) -> bool:
        return bool(self.url) and self.status in ("queued", "running")


def _request(url: str, body: dict[str, Any] | None, timeout_s: float, method: str = "") -> bytes:
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(
        url,
        data=data,
        headers={"Content-Type": "application/json"} if data else {},
        method=method or ("POST" if data else "GET"),
    )
    with urllib.request.urlopen(req, timeout=timeout_s) as response:
        return bytes(response.read())


def api_json(url: str, body: dict[str, Any] | None = None, timeout_s: float = 10.0) -> Any:
    """GET `url` (POST `body` when given) and parse the API's JSON answer: the HTTP the job
    panel's watcher speaks, for the viewer's other followers (web/surface_jobs.py)."""
    return json.loads(_request(url, body, timeout_s))


def api_failure(exc: Exception, api: str = "the API's address") -> str:
    """Why a call to the API failed, in the job panel's words (web/job_words.py)."""
    return problem(exc, api)[1]


def view_of(job: dict[str, Any], api: str, key: int) -> JobView:
    """The API's job JSON as the panel shows it."""
    eta = job.get("eta_s")
    return JobView(
        id=job["id"],
        kind=job["kind"],
        status=job["status"],
        progress=float(job.get("progress") or 0.0),
        message=job.get("error") or job.get("note") or "",
        url=f"{api}/v1/jobs/{job['id']}",
        key=key,
        eta_s=None if eta is None else float(eta),
    )


class JobWatcher:
    """The jobs this viewer submitted or opened, newest first, each followed by its thread."""

    def __init__(self, poll_s: float = 1.0, timeout_s: float = 10.0) -> None:
        self.poll_s = poll_s
        self.timeout_s = timeout_s
        self._views: dict[int, JobView] = {}  # key -> view, oldest first
        self._next = 0
        self._lock = threading.Lock()
        self.version = 0  # bumps at every change: the panel's redraw key

    @property
    def view(self) -> JobView:
        """The newest job (a blank view before the first)."""
        with self._lock:
            return next(reversed(self._views.values()), JobView())

    @property
    def views(self) -> tuple[JobView, ...]:
        """Every job listed, newest first."""
        with self._lock:
            return tuple(reversed(self._views.values()))

    def get(self, key: int) -> JobView | None:
        with self._lock:
            return self._views.get(key)

    def submit(self, api_url: str, body: dict[str, Any]) -> int:
        """POST `body` to the API's jobs and follow the job it makes; its key in the list."""
        return self._start(api_url, body, None)

    def open(self, api_url: str, job_id: str) -> int:
        """Follow an existing job (any kind) by its id: its progress, then its figure."""
        return self._start(api_url, None, job_id.strip())

    def cancel(self, key: int) -> bool:
        """Ask the API to cancel job `key` (DELETE, on a thread of its own); False when it is
        not a queued or running job of this list."""
        view = self.get(key)
        if view is None or not view.cancellable:
            return False
        threading.Thread(target=self._cancel, args=(view,), name="job-cancel", daemon=True).start()
        return True

    def _start(self, api_url: str, body: dict[str, Any] | None, job_id: str | None) -> int:
        kind = str(body.get("kind", "")) if body else ""
        with self._lock:
            self._next += 1
            key = self._next
            if job_id:  # opened again: one row per job
                for k in [k for k, v in self._views.items() if v.id == job_id]:
                    del self._views[k]
            self._views[key] = JobView(id=job_id or "", kind=kind, status="submitting", key=key)
            while len(self._views) > KEEP:
                del self._views[next(iter(self._views))]  # the oldest is no longer followed
            self.version += 1
        threading.Thread(
            target=self._follow,
            args=(key, api_url.rstrip("/"), body, job_id),
            name="job-watcher",
            daemon=True,
        ).start()
        return key

    def _set(self, view: JobView) -> bool:
        """Publish `view` unless its job left the list; False: stop following it."""
        with self._lock:
            if view.key not in self._views:
                return False
            self._views[view.key] = view
            self.version += 1
            return True

    def _follow(self, key: int, api: str, body: dict[str, Any] | None, job_id: str | None) -> None:
        view = self.get(key) or JobView(key=key)
        try:
            url = f"{api}/v1/jobs" if body is not None else f"{api}/v1/jobs/{job_id}"
            job = json.loads(_request(url, body, self.timeout_s))
            while True:
                view = view_of(job, api, key)
                if not self._set(view):
                    return
                if job["status"] in TERMINAL:
                    break
                time.sleep(self.poll_s)
                job = json.loads(_request(view.url, None, self.timeout_s))
            if job["status"] == "done":
                self._set(self._done(view, job.get("spec") or {}))
        except Exception as exc:  # the API absent, refusing, or answering nonsense
            status, message = problem(exc, api)
            if view.status in ("none", "submitting"):
                view = replace(view, status=status)
            self._set(replace(view, message=message))

    def _done(self, view: JobView, spec: dict[str, Any]) -> JobView:
        """A done job's figure and, for a kind the panels draw, its run to replay."""
        png = _request(f"{view.url}/figure.png", None, 60.0)
        if view.kind not in REPLAYABLE:
            return replace(view, figure_png=png)
        result = json.loads(_request(f"{view.url}/result", None, 60.0))
        return replace(
            view,
            figure_png=png,
            d31_series=first_run_d31(result),
            replay=replay_of(view.kind, view.id, spec, result),
        )

    def _cancel(self, view: JobView) -> None:
        api = view.url.split("/v1/jobs/")[0]
        try:
            job = json.loads(_request(view.url, None, self.timeout_s, "DELETE"))
            self._set(view_of(job, api, view.key))
        except Exception as exc:  # already finished (409), no token (401), API gone
            now = self.get(view.key) or view
            self._set(replace(now, message=f"not cancelled: {problem(exc, api)[1]}"))

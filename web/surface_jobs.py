"""Drift surfaces this viewer asks the service for, one `surface` job per condition.

When no surface exists for the walk's ground, mass and slope, the drift-surface panel offers to
compute one: the request body is the REST `surface` kind's (docs/API.md; the service validates
it), over `SURFACE_JOB_BETAS`. Each job is followed by its own daemon thread, apart from the job
panel's watcher (web/jobs.py), so that a long surface never hides the run a person submitted;
HTTP never runs on the loop thread. The result (`GET /v1/jobs/{id}/result`) is validated with
the core's `DriftSurface` and kept for this session; the panel then draws it (web/surfaces.py).
"""

from __future__ import annotations

import threading
import time
from dataclasses import replace
from typing import Any

from pydantic import ValidationError

from sim_core.contract import DriftSurface
from web.bifurcation import first_error
from web.conditions import Conditions, of_surface
from web.jobs import TERMINAL, JobView, api_failure, api_json, view_of

# The atlas's betas (`insect-gait atlas`: 0.60-0.72, 0.01 apart): the paper's window and past
# it, where the gaits change. Fig. 8's 25-beta surface took 2,258 core-s (docs/NUMERICS.md),
# so this one takes about 1,200 core-s: minutes on a workstation, ~10 on a 2-core host.
SURFACE_JOB_BETAS = {"start": 0.60, "stop": 0.72, "steps": 13}


def surface_job_body(want: Conditions) -> dict[str, Any]:
    """The `surface` job that computes the drift surface of `want` (on its sliders' grid)."""
    c = want.snapped()
    return {
        "kind": "surface",
        "beta_range": dict(SURFACE_JOB_BETAS),
        "body_mass_g": c.body_mass_g,
        "slope_deg": c.slope_deg,
        "ground": c.ground,
    }


def surface_of(result: dict[str, Any], want: Conditions) -> tuple[DriftSurface | None, str]:
    """The surface in a job's stored result (`GET .../result`), validated, and a note ("" when
    it is one of `want`'s conditions)."""
    try:
        surface = DriftSurface.model_validate(result.get("result", {}).get("surface"))
    except ValidationError as exc:
        return None, f"the job's result is not a DriftSurface: {first_error(exc)}"
    got = of_surface(surface)
    if not got.matches(want):
        return None, f"the job computed {got.label()}, not {want.label()}"
    return surface, ""


class SurfaceJobs:
    """The surface jobs this viewer submitted, by condition, and the surfaces they returned."""

    def __init__(self, poll_s: float = 1.0, timeout_s: float = 10.0) -> None:
        self.poll_s = poll_s
        self.timeout_s = timeout_s
        self._lock = threading.Lock()
        self._views: dict[tuple[str, int, int], JobView] = {}
        self._surfaces: dict[tuple[str, int, int], DriftSurface] = {}
        self.version = 0  # bumps whenever a job's state or a surface changes: a redraw key

    def view(self, want: Conditions) -> JobView | None:
        """The latest job for `want`'s conditions (None: none submitted)."""
        with self._lock:
            return self._views.get(want.key)

    def surfaces(self) -> list[DriftSurface]:
        """The surfaces computed in this session, latest first."""
        with self._lock:
            return list(reversed(self._surfaces.values()))

    def submit(self, api_url: str, want: Conditions) -> bool:
        """POST the surface of `want` and follow it; False when one for it is already under
        way (a second click must not queue the same hour of work twice)."""
        with self._lock:
            running = self._views.get(want.key)
            if running is not None and not running.finished:
                return False
            self._views[want.key] = JobView(kind="surface", status="submitting")
            self.version += 1
        threading.Thread(
            target=self._follow,
            args=(api_url.rstrip("/"), want),
            name="surface-job",
            daemon=True,
        ).start()
        return True

    def _set(self, want: Conditions, view: JobView, surface: DriftSurface | None = None) -> None:
        with self._lock:
            self._views[want.key] = view
            if surface is not None:
                self._surfaces.pop(want.key, None)  # re-inserted: the latest goes last
                self._surfaces[want.key] = surface
            self.version += 1

    def _follow(self, api: str, want: Conditions) -> None:
        view = JobView(kind="surface", status="submitting")
        try:
            job = api_json(f"{api}/v1/jobs", surface_job_body(want), self.timeout_s)
            while True:
                view = view_of(job, api, key=0)  # one job per condition: no list key
                self._set(want, view)
                if job["status"] in TERMINAL:
                    break
                time.sleep(self.poll_s)
                job = api_json(view.url, None, self.timeout_s)
            if job["status"] == "done":
                surface, note = surface_of(api_json(f"{view.url}/result", None, 60.0), want)
                if surface is None:
                    self._set(want, replace(view, status="failed", message=note))
                else:
                    self._set(want, view, surface)
        except Exception as exc:  # the API absent, refusing, or answering nonsense
            self._set(want, replace(view, status="unreachable", message=api_failure(exc)))

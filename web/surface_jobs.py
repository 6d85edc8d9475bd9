"""Drift surfaces this viewer asks the service for, one `surface` job per condition.

When no surface exists for the walk's ground, mass and slope, the drift-surface panel offers to
compute one: the request body is the REST `surface` kind's (docs/API.md; the service validates
it), over `SURFACE_JOB_BETAS`. Each job is followed by its own daemon thread, apart from the job
panel's watcher (web/jobs.py), so that a long surface never hides the run a person submitted;
HTTP never runs on the loop thread. The result (`GET /v1/jobs/{id}/result`) is validated with
the core's `DriftSurface` and kept for this session; the panel then draws it (web/surfaces.py).
"""

from __future__ import annotations

import json
import threading
import time
from dataclasses import replace
from typing import Any

from pydantic import ValidationError

from sim_core.contract import DriftSurface, ModelChoice
from web.bifurcation import first_error
from web.conditions import Conditions, model_of, of_surface, same_model
from web.jobs import TERMINAL, JobView, api_failure, api_json, view_of

# The atlas's betas (`insect-gait atlas`: 0.60-0.72, 0.01 apart): the paper's window and past
# it, where the gaits change. Fig. 8's 25-beta surface took 2,258 core-s (docs/NUMERICS.md),
# so this one takes about 1,200 core-s: minutes on a workstation, ~10 on a 2-core host.
SURFACE_JOB_BETAS = {"start": 0.60, "stop": 0.72, "steps": 13}
Key = tuple[tuple[str, int, int], str]  # a job's: its conditions' key and its model's leaves


def surface_job_body(want: Conditions, model: ModelChoice | None = None) -> dict[str, Any]:
    """The `surface` job that computes the drift surface of `want` (on its sliders' grid) with
    the walk's model parameters (`model`, the contract's `ModelChoice` on `want`'s ground:
    its ground, setting and leaves as every job takes them; None: the defaults)."""
    c = want.snapped()
    return {
        "kind": "surface",
        "beta_range": dict(SURFACE_JOB_BETAS),
        "body_mass_g": c.body_mass_g,
        "slope_deg": c.slope_deg,
    } | model_of(want, model).body()


def surface_of(
    result: dict[str, Any], want: Conditions, model: ModelChoice | None = None
) -> tuple[DriftSurface | None, str]:
    """The surface in a job's stored result (`GET .../result`), validated, and a note ("" when
    it is of `want`'s conditions and `model`'s parameters)."""
    try:
        surface = DriftSurface.model_validate(result.get("result", {}).get("surface"))
    except ValidationError as exc:
        return None, f"the job's result is not a DriftSurface: {first_error(exc)}"
    got, m = of_surface(surface), model_of(want, model)
    if not got.matches(want):
        return None, f"the job computed {got.label()}, not {want.label()}"
    if not same_model(surface, m):
        return None, f"the job computed other model parameters than {m.words()}"
    return surface, ""


def _key(want: Conditions, model: ModelChoice) -> Key:
    """One job per condition and model (the leaves it changes: a setting and the same leaves
    typed out are one model)."""
    return want.key, json.dumps(model.changed(), sort_keys=True)


class SurfaceJobs:
    """The surface jobs this viewer submitted, by condition, and the surfaces they returned."""

    def __init__(self, poll_s: float = 1.0, timeout_s: float = 10.0) -> None:
        self.poll_s = poll_s
        self.timeout_s = timeout_s
        self._lock = threading.Lock()
        self._views: dict[Key, JobView] = {}
        self._surfaces: dict[Key, DriftSurface] = {}
        self.version = 0  # bumps whenever a job's state or a surface changes: a redraw key

    def state(
        self, want: Conditions, model: ModelChoice | None = None
    ) -> tuple[list[DriftSurface], JobView | None]:
        """The surfaces computed in this session (latest first) and the latest job for
        `want`'s conditions and `model` (None: none submitted), read under one lock: read
        apart, a job that finishes between the two reads looks finished without its surface,
        and the panel offers to compute it again."""
        with self._lock:
            surfaces = list(reversed(self._surfaces.values()))
            return surfaces, self._views.get(_key(want, model_of(want, model)))

    def submit(self, api_url: str, want: Conditions, model: ModelChoice | None = None) -> bool:
        """POST the surface of `want` with `model`'s parameters (None: the defaults) and follow
        it; False when one for it is already under way (a second click must not queue the
        same hour of work twice)."""
        m = model_of(want, model)
        key = _key(want, m)
        with self._lock:
            running = self._views.get(key)
            if running is not None and not running.finished:
                return False
            self._views[key] = JobView(kind="surface", status="submitting")
            self.version += 1
        threading.Thread(
            target=self._follow,
            args=(api_url.rstrip("/"), want, m),
            name="surface-job",
            daemon=True,
        ).start()
        return True

    def _set(self, key: Key, view: JobView, surface: DriftSurface | None = None) -> None:
        with self._lock:
            self._views[key] = view
            if surface is not None:
                self._surfaces.pop(key, None)  # re-inserted: the latest goes last
                self._surfaces[key] = surface
            self.version += 1

    def _follow(self, api: str, want: Conditions, model: ModelChoice) -> None:
        view, key = JobView(kind="surface", status="submitting"), _key(want, model)
        try:
            job = api_json(f"{api}/v1/jobs", surface_job_body(want, model), self.timeout_s)
            while True:
                view = view_of(job, api, key=0)  # one job per condition: no list key
                if job["status"] in TERMINAL:
                    break
                self._set(key, view)
                time.sleep(self.poll_s)
                job = api_json(view.url, None, self.timeout_s)
            # a finished job is published with its surface, never before it: between the two
            # the panel would offer to compute the surface being fetched (a second job)
            if job["status"] != "done":
                self._set(key, view)
                return
            answer = api_json(f"{view.url}/result", None, 60.0)
            surface, note = surface_of(answer, want, model)
            if surface is None:
                self._set(key, replace(view, status="failed", message=note))
            else:
                self._set(key, view, surface)
        except Exception as exc:  # the API absent, refusing, or answering nonsense
            self._set(key, replace(view, status="unreachable", message=api_failure(exc)))

"""What the loop draws (loop thread only): the readouts and status line, the footfall, Delta31
and return-map panels, the bifurcation, atlas, drift-surface and ramp-path panels, and the job
bodies; each panel rebuilt only when its inputs changed, at rates the loop sets."""

from __future__ import annotations

import html
import json
import math
from collections.abc import Callable, Hashable

import viser

from sim_core import return_map_from_series
from sim_core.contract import (
    ATLAS_AXES,
    AXIS_LABEL,
    RETURN_MAP_SKIP,
)
from web import controls, export
from web.atlas_svg import atlas_svg
from web.bifurcation import finder_points
from web.bifurcation_svg import bifurcation_svg, ramp_path_svg
from web.conditions import Conditions, atlas_conditions, atlas_holds, atlas_label, events_of
from web.d31_svg import d31_svg
from web.footfall_svg import footfall_svg
from web.jobs import job_status_html
from web.readouts import Readouts
from web.record import d31_since, footfall_bars
from web.replaying import Replaying
from web.return_map_plot import return_map_data
from web.surface_svg import surface_svg
from web.surfaces import pick_finder, pick_surface


class Drawing(Replaying):
    """The panels and readouts, drawn from the simulation's own record."""

    def _draw_readouts(
        self, rtf: float | None, stepping_rtf: float | None, frame_hz: float | None
    ) -> None:
        """Controls the loop changed, the readouts and the status line (cheap: a few short
        strings, each sent only when it changed)."""
        sim = self.sim
        ramp = ""
        if self.ramp is not None:
            r = self.ramp
            elapsed = sim.time_s - self._ramp_t0
            value = getattr(sim, r.param)
            ramp = (
                f"{controls.RAMP_LABELS[r.param]} {sim.ramp_phase}: {value:.3f} "
                f"({min(elapsed, r.duration_s):.0f} of {r.duration_s:.0f} s)"
            )
        write, self._write = self._write, {}
        self.panels.sync_controls(
            self.playing, None if self.ramp is None else self.ramp.param, write
        )
        gait = sim.gait
        heading = sim.heading_rad
        self.panels.show_readouts(
            Readouts(
                beta=sim.beta,
                time_s=sim.time_s,
                speed_cm_s=sim.speed_cm_s,
                duty_factor=sim.duty_factor,
                gait=gait,
                d31_now=sim.d31_now,
                rtf=rtf,
                stepping_rtf=stepping_rtf,
                target_speed=self.speed,
                frame_hz=frame_hz,
                ramp=ramp,
                error=self.error,
                playing=self.playing,
                body_mass_g=sim.body_mass_g,
                slope_deg=sim.slope_deg,
                heading_deg=None if heading is None else math.degrees(heading),
                ground=self.ground,
                lag_s=self._clock.lag_s,
            )
        )
        speed = controls.speed_label(self.speed) or controls.DEFAULT_SPEED
        ramp_param = self.ramp.param if self.ramp is not None else self.panels.ramp_param_name
        self.panels.show_choices(
            {
                "speed": speed,
                "camera": self.scene.follow,
                "ground": controls.GROUND_LABEL[self.ground],
                "ramp drives": controls.RAMP_LABELS.get(ramp_param, ramp_param),
                "atlas over": self.panels.atlas_axis,
            }
        )
        self.panels.show_html(self.panels.job, job_html(self.settings()))
        view = self.jobs.view
        if view is not self._job_shown:
            self._job_shown = view
            self.panels.show_html(self.panels.job_status, job_status_html(view))
        self._show_jobs()  # the job list's rows (web/replaying.py)

    def _draw_panels(self) -> None:
        """The footfall diagram, Delta31 and the return map, each rebuilt only when its inputs
        changed; a replayed job's run first, in the panels it fills (web/replaying.py)."""
        self._draw_replay()
        sim = self.sim
        gait = sim.gait
        t_now, window = sim.time_s, self.footfall_window_s
        self._redraw(
            self.panels.footfall,
            (self._walk, t_now, window),
            lambda: footfall_svg(footfall_bars(sim, window), t_now, window),
        )
        w, events, job = self.d31_window_s, sim.d31_events, self.jobs.view
        self._redraw(
            self.panels.d31,
            (self._walk, len(events), t_now, w, gait, job.id, len(job.d31_series)),
            lambda: d31_svg(
                events if w is None else d31_since(events, t_now - w),
                t_now,
                w,
                gait,
                self.d31_conditions.marks,
                (job.id[:8], job.d31_series) if job.d31_series else None,
            ),
        )
        if self._changed(self.panels.return_map, (self._walk, len(events), sim.beta)):
            self.panels.return_map.data = return_map_data(self._return_map())

    def _changed(self, handle: object, key: Hashable) -> bool:
        """Whether `key`, the inputs a panel is drawn from (the walk, the record's length or
        time, the window), changed since it was last drawn: an idle plot costs nothing."""
        if self._drawn.get(id(handle)) == key:
            return False
        self._drawn[id(handle)] = key
        return True

    def _redraw(self, handle: viser.GuiHtmlHandle, key: Hashable, build: Callable[[], str]) -> None:
        """Rebuild an SVG panel only when its inputs changed (`_changed`), unless a replayed
        job's run fills it."""
        if self.replayed(handle):
            return
        if self._changed(handle, key):
            self.panels.show_html(handle, build())

    def _return_map(self) -> list[tuple[float, float]]:
        """The current run's (Delta31 n, n + 4) pairs, the latest `return_map_len`, built by
        the core's return-map construction (first RETURN_MAP_SKIP of the run dropped)."""
        events = self.sim.d31_events
        recent = events[-(self.cfg.return_map_len + 4) :]
        whole = len(recent) == len(events)
        rm = return_map_from_series(
            self.sim.beta, [[d for _, d in recent]], lag=4, skip=RETURN_MAP_SKIP if whole else 0
        )
        return list(zip(rm.x.tolist(), rm.y.tolist(), strict=True))

    def _draw_bifurcation(self) -> None:
        """The bifurcation, atlas and drift-surface panels, each of the walk's own conditions
        (web/conditions.py): data of other conditions is not drawn, the live point and this
        run's trail only where they were taken under the conditions the panel names."""
        self._draw_ramp_path()
        want = self.walk_conditions()
        label = want.label()
        finder, note = pick_finder(self.bifurcation, want)
        trail = events_of(self.d31_conditions.events(self.sim, -self.cfg.trail_len), want)
        last = self.d31_conditions.events(self.sim, -1)
        live = (self.sim.beta, last[0].d31 if events_of(last, want) else None)
        beta_range = (controls.BETA.lo, controls.BETA.hi)
        ramp = self.d31_conditions.ramp_path(self.sim) if self._ramp_draws_on_beta() else []
        points = None if finder is None else finder_points(finder)
        self.panels.show_html(self.panels.bifurcation, bifurcation_svg(
            points, note, trail, live, beta_range, events_of(ramp, want), conditions=label
        ))  # fmt: skip
        self._draw_atlas(want)
        pick = pick_surface(self.surfaces, self.surface_jobs, want)
        if self.panels.surface_compute.visible != pick.offer:
            self.panels.surface_compute.visible = pick.offer
        # the map (~80 kB of SVG) is rebuilt only when what it shows changes or the live point
        # enters another cell of the surface's grid (0.005 in beta, 0.05 rad): a walk that
        # drifts slowly costs the browser a redraw every few seconds, not every 0.4 s
        d31 = live[1] if pick.surface is not None else None
        cell = (round(self.sim.beta / 0.005), None if d31 is None else round(d31 / 0.05))
        self._redraw(
            self.panels.surface,
            (pick.key, pick.note, cell, beta_range),
            lambda: surface_svg(
                pick.surface, pick.note, (live[0], d31), beta_range, conditions=label
            ),
        )

    def _draw_atlas(self, want: Conditions) -> None:
        """The atlas of the walk's ground over mass or slope; the live point only when the
        walk is at the value the atlas holds the other parameter at."""
        axis = self.panels.atlas_axis if self.panels.atlas_axis in ATLAS_AXES else "mass"
        atlas, anote = self.atlases[(axis, self.ground)].get()
        held = atlas_conditions(self.ground)
        value = self.sim.body_mass_g if axis == "mass" else self.sim.slope_deg
        self.panels.show_html(
            self.panels.atlas,
            atlas_svg(
                atlas,
                anote,
                axis,
                AXIS_LABEL.get(axis, axis),
                (self.sim.beta, value) if atlas_holds(axis, held, want) else None,
                (controls.BETA.lo, controls.BETA.hi),
                conditions=atlas_label(axis, held),
            ),
        )

    def _draw_ramp_path(self) -> None:
        """The latest ramp's path on its own axes (the ramped parameter across), as it goes."""
        ramp = self._last_ramp
        if ramp is None:
            return
        path = self.d31_conditions.ramp_path(self.sim)
        value_range = controls.ramp_range(ramp)
        self._redraw(
            self.panels.ramp_plot,
            (self._walk, ramp, len(path)),
            lambda: ramp_path_svg(
                path, ramp.param, controls.RAMP_LABELS.get(ramp.param, ramp.param), value_range
            ),
        )

    def _ramp_draws_on_beta(self) -> bool:
        """A ramp's path goes on the (beta, Delta31) panel when it ramped beta."""
        return self._last_ramp is not None and self._last_ramp.param == "beta"


def job_html(s: export.Settings) -> str:
    """The current settings as REST job bodies to copy, with the curl line and the URL."""
    url = s.api_url.rstrip("/")
    parts = [
        f'<div data-job-url="{html.escape(url)}/v1/jobs" style="font-size:0.8em">',
        f"<b>POST</b> <code>{html.escape(url)}/v1/jobs</code> "
        f'(<a href="{html.escape(url)}/docs" target="_blank">API docs</a>)',
    ]
    for kind, body in export.jobs(s).items():
        text = json.dumps(body, indent=1)
        parts.append(
            f"<div>a <b>{kind}</b> job{' (the ramp set up above)' if kind == 'hysteresis' else ''}:"
            f'</div><pre data-job="{kind}" style="white-space:pre-wrap;user-select:all;'
            f'margin:2px 0;padding:3px;background:#f4f4f4">{html.escape(text)}</pre>'
            f'<pre style="white-space:pre-wrap;user-select:all;margin:2px 0;font-size:0.9em">'
            f"{html.escape(export.curl(url, body))}</pre>"
        )
    parts.append("</div>")
    return "".join(parts)

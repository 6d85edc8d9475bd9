"""The panels of the gaits' maps (loop thread only): the bifurcation, the atlas, the drift
surface and a ramp's path, each of the walk's own conditions (web/conditions.py): data of other
conditions is not drawn, the live point and this run's trail only where they were taken under
the conditions the panel names. It reads the results folder's files (re-read when they change)
and the surface jobs of this session; web/painter.py's `Redraws` says what changed.
"""

from __future__ import annotations

from pathlib import Path

from sim_core.contract import (
    ATLAS_AXES,
    AXIS_LABEL,
    FinderOutput,
    SurfaceAtlas,
    surface_atlas_file,
)
from web import controls
from web.atlas_svg import atlas_svg
from web.bifurcation import WatchedFile, finder_points
from web.bifurcation_svg import bifurcation_svg, ramp_path_svg
from web.conditions import Conditions, atlas_conditions, atlas_holds, atlas_label, events_of
from web.painter import Redraws
from web.panels import Panels
from web.state import LoopConfig, ViewerState
from web.surface_jobs import SurfaceJobs
from web.surface_svg import surface_svg
from web.surfaces import SurfaceFiles, pick_finder, pick_surface


class ChartPainter:
    """Draws the bifurcation, atlas, drift-surface and ramp-path panels from the results
    folder of `bifurcation_path` (the finder's file; the atlases and surfaces beside it)."""

    def __init__(
        self,
        state: ViewerState,
        panels: Panels,
        *,
        surface_jobs: SurfaceJobs,
        redraws: Redraws,
        config: LoopConfig,
        bifurcation_path: Path,
        surface_path: Path,
    ) -> None:
        self._state, self._panels, self._surface_jobs = state, panels, surface_jobs
        self._redraws, self._cfg = redraws, config
        self._bifurcation = WatchedFile(bifurcation_path, FinderOutput, "finder results")
        self._atlases: dict[tuple[str, str], WatchedFile[SurfaceAtlas]] = {
            (axis, g): WatchedFile(
                surface_atlas_file(bifurcation_path.parent, axis, g), SurfaceAtlas, "atlas"
            )
            for axis in ATLAS_AXES
            for g in controls.GROUND_LABEL
        }
        # the results folder's drift surfaces and this session's surface jobs (web/surfaces.py)
        self._surfaces = SurfaceFiles(bifurcation_path.parent, surface_path)

    def draw(self) -> None:
        """Every map panel of the walk's conditions now."""
        self._redraws.replay()
        self._ramp_path()
        state, panels, sim = self._state, self._panels, self._state.sim
        want = state.conditions()
        label = want.label()
        finder, note = pick_finder(self._bifurcation, want)
        trail = events_of(state.d31_conditions.events(sim, -self._cfg.trail_len), want)
        last = state.d31_conditions.events(sim, -1)
        live = (sim.beta, last[0].d31 if events_of(last, want) else None)
        beta_range = (controls.BETA.lo, controls.BETA.hi)
        ramp = state.d31_conditions.ramp_path(sim) if self._ramp_on_beta() else []
        points = None if finder is None else finder_points(finder)
        panels.show_html(panels.bifurcation, bifurcation_svg(
            points, note, trail, live, beta_range, events_of(ramp, want), conditions=label
        ))  # fmt: skip
        self._atlas(want)
        pick = pick_surface(self._surfaces, self._surface_jobs, want, state.model)
        if panels.surface_compute.visible != pick.offer:
            panels.surface_compute.visible = pick.offer
        # the map (~80 kB of SVG) is rebuilt only when what it shows changes or the live point
        # enters another cell of the surface's grid (0.005 in beta, 0.05 rad): a walk that
        # drifts slowly costs the browser a redraw every few seconds, not every 0.4 s
        d31 = live[1] if pick.surface is not None else None
        cell = (round(sim.beta / 0.005), None if d31 is None else round(d31 / 0.05))
        self._redraws.redraw(
            panels.surface,
            (pick.key, pick.note, cell, beta_range),
            lambda: surface_svg(
                pick.surface, pick.note, (live[0], d31), beta_range, conditions=label
            ),
        )

    def _atlas(self, want: Conditions) -> None:
        """The atlas of the walk's ground over mass or slope; the live point only when the
        walk is at the value the atlas holds the other parameter at."""
        state, panels = self._state, self._panels
        axis = panels.atlas_axis if panels.atlas_axis in ATLAS_AXES else "mass"
        atlas, anote = self._atlases[(axis, state.ground)].get()
        held = atlas_conditions(state.ground)
        value = state.sim.body_mass_g if axis == "mass" else state.sim.slope_deg
        panels.show_html(
            panels.atlas,
            atlas_svg(
                atlas,
                anote,
                axis,
                AXIS_LABEL.get(axis, axis),
                (state.sim.beta, value) if atlas_holds(axis, held, want) else None,
                (controls.BETA.lo, controls.BETA.hi),
                conditions=atlas_label(axis, held),
            ),
        )

    def _ramp_path(self) -> None:
        """The latest ramp's path on its own axes (the ramped parameter across), as it goes."""
        state = self._state
        ramp = state.last_ramp
        if ramp is None:
            return
        path = state.d31_conditions.ramp_path(state.sim)
        value_range = controls.ramp_range(ramp)
        self._redraws.redraw(
            self._panels.ramp_plot,
            (state.walk, ramp, len(path)),
            lambda: ramp_path_svg(
                path, ramp.param, controls.RAMP_LABELS.get(ramp.param, ramp.param), value_range
            ),
        )

    def _ramp_on_beta(self) -> bool:
        """A ramp's path goes on the (beta, Delta31) panel when it ramped beta."""
        ramp = self._state.last_ramp
        return ramp is not None and ramp.param == "beta"

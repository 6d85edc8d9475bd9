"""Which drift surface and which finder results the panels draw: those of the walk's own
ground, mass and slope (web/conditions.py), or a sentence saying there are none.

A surface of other model parameters than the walk's is not its map either: the walk's
`ModelChoice` picks among them by the leaves each records (`same_model`), and a surface job
asks for the walk's (web/surface_jobs.py). Where surfaces come from: the results folder
(`surface*.json` there, each validated as the core's `DriftSurface`: `insect-gait reproduce`
writes surface.json on the constraint ground and surface_penalty.json on the penalty ground;
`--surface PATH` adds a file, looked at first) and the surfaces this viewer's `surface` jobs
returned in this session (web/surface_jobs.py), which are preferred: they are the newest. The
runs cache holds probes, not surfaces (one file per task, `sim_core.runs.cache`), so it is not
searched. The finder's results are the one bifurcation file, cut to the cells of the walk's
conditions.
"""

from __future__ import annotations

from collections.abc import Hashable
from dataclasses import dataclass
from pathlib import Path

from sim_core.contract import DriftSurface, FinderOutput, ModelChoice
from web.bifurcation import WatchedFile
from web.conditions import (
    Conditions,
    finder_conditions,
    finder_for,
    model_of,
    of_surface,
    same_model,
)
from web.panel_labels import COMPUTE_SURFACE
from web.surface_jobs import SURFACE_JOB_BETAS, SurfaceJobs

SURFACE_GLOB = "surface*.json"
ATLAS_PREFIX = "surface_atlas_"  # SurfaceAtlas files share the prefix: not surfaces


class SurfaceFiles:
    """The drift surfaces of the results folder, each re-read when it changes."""

    def __init__(self, folder: Path, first: Path | None = None) -> None:
        self.folder = folder
        self.first = first
        self._watched: dict[Path, WatchedFile[DriftSurface]] = {}

    def paths(self) -> list[Path]:
        """`first`, then the folder's surface*.json but the atlases, in name order."""
        try:
            found = sorted(self.folder.glob(SURFACE_GLOB))
        except OSError:
            found = []
        found = [p for p in found if not p.name.startswith(ATLAS_PREFIX)]
        head = [self.first] if self.first is not None else []
        return list(dict.fromkeys(head + found))

    def read(self) -> list[tuple[WatchedFile[DriftSurface], DriftSurface | None, str]]:
        """Each file with its surface (None: absent or invalid) and its note."""
        out = []
        for p in self.paths():
            w = self._watched.get(p)
            if w is None:
                w = self._watched[p] = WatchedFile(p, DriftSurface, "drift surface")
            surface, note = w.get()
            out.append((w, surface, note))
        return out


@dataclass(frozen=True)
class Pick:
    """What the drift-surface panel shows: a surface of the walk's conditions, or a note."""

    surface: DriftSurface | None
    note: str
    key: Hashable  # changes whenever what is drawn changes (a redraw key)
    offer: bool  # whether to offer computing it (none exists and none is under way)


def pick_surface(
    files: SurfaceFiles, jobs: SurfaceJobs, want: Conditions, model: ModelChoice | None = None
) -> Pick:
    """The surface of `want`'s conditions and `model`'s parameters (None: the defaults), this
    session's jobs first, then the files."""
    m = model_of(want, model)

    def mine(s: DriftSurface) -> bool:
        return of_surface(s).matches(want) and same_model(s, m)

    done, view = jobs.state(want, m)
    for s in done:
        if mine(s):
            return Pick(s, "", ("job", want.key, jobs.version), False)
    read = files.read()
    for w, found, _ in read:
        if found is not None and mine(found):
            return Pick(found, "", (str(w.path), w.version, want.key), False)
    key = ("none", want.key, jobs.version, tuple(w.version for w, _, _ in read), m.words())
    label = want.label() + (f" (model: {m.words()})" if m.changed() else "")
    if view is not None and not view.finished:
        pct = f" {100 * view.progress:.0f}%" if view.status == "running" else ""
        ident = f" (job {view.id})" if view.id else ""
        note = f"computing the drift surface for {label}: {view.status}{pct}{ident}"
        return Pick(None, note, key, False)
    held = [of_surface(s).label() for _, s, _ in read if s is not None]
    bad = [n for w, s, n in read if s is None and w.path.exists()]  # present, not valid
    span = f"β {SURFACE_JOB_BETAS['start']:g}-{SURFACE_JOB_BETAS['stop']:g}"
    # what to do first: a long note is cut at the panel's fifth line (its tooltip keeps all)
    parts = [f"no drift surface for {label}: press '{COMPUTE_SURFACE}' below (a job, {span})"]
    if view is not None:
        parts.append(f"its last job {view.status}: {view.message or 'no reason given'}")
    if held:
        parts.append(f"the results folder has {' and '.join(held)}")
    note = "; ".join(parts + bad[:1])
    return Pick(None, note, key, True)


def pick_finder(
    watched: WatchedFile[FinderOutput], want: Conditions
) -> tuple[FinderOutput | None, str]:
    """The finder's cells of `want`'s conditions, or None and why not."""
    out, note = watched.get()
    if out is None:
        return None, note  # absent or invalid: the title names the walk's conditions
    mine = finder_for(out, want)
    if mine is not None:
        return mine, ""
    held = "; ".join(c.label() for c in finder_conditions(out)) or "no cells"
    return None, (
        f"no finder results for {want.label()} ({watched.path.name} holds {held}); the drift "
        "surface shows this condition's gaits, a `bifurcation` job finds them by walking"
    )

"""What the finder kinds (bifurcation) share: their request base, the finder's runs as cached
task rounds, its output as flat rows, and those rows drawn against beta."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field

import sim_core
from server.kinds.base import Physics, Row
from server.kinds.bounds import DURATION_BOUNDS, IntLike, bounded
from server.kinds.compute import Compute
from server.kinds.progress import ChunkProgress
from sim_core.contract import Cell, CellResult, FinderConfig, Probe, RunFn

if TYPE_CHECKING:
    from matplotlib.axes import Axes


class FinderRow(Row):
    """One point the finder reports: stable, one-sided, unstable, ghost or not settled."""

    beta: float = Field(description="duty factor")
    body_mass_g: float = Field(description="body mass, g")
    slope_deg: float = Field(description="slope, deg")
    kind: Literal["stable", "one-sided", "unstable", "ghost", "not settled"] = Field(
        description="what the point is"
    )
    d31: float | None = Field(description="its Delta31, rad (not settled: the run's final)")
    gait: str | None = Field(description="an attractor's gait")
    starts: int | None = Field(description="an attractor's spread starts that end there")
    slope: float | None = Field(description="the n -> n+4 map's slope at it")
    drift: float | None = Field(description="drift per cycle, rad")


FINDER_DEFAULTS = FinderConfig()


class Finder(Physics):
    """Kinds answered by the settled fixed-point finder (`sim_core.find`): settled
    runs from starts spread over the circle, judged by the core's one settled rule."""

    starts: IntLike = bounded(
        FINDER_DEFAULTS.starts, "starts", "starts spread over the circle per beta", ge=2, le=16
    )
    duration_s: float = bounded(
        FINDER_DEFAULTS.duration_s, "duration_s",
        "simulated time of each start's run, s (the settled rule needs a last quarter of "
        "40 gait cycles, ~16-20 s; near a fold 40 s tells a ghost from a gait)",
        ge=2.0, le=DURATION_BOUNDS["le"],
    )  # fmt: skip

    def run_count(self) -> int:
        return self.cells() * (self.starts + self.extra_runs_per_cell())

    def sim_seconds_per_run(self) -> float:
        return self.duration_s

    def total_sim_seconds(self) -> float:
        return self.cells() * (self.starts * self.duration_s + self.extra_sim_seconds_per_cell())

    def cells(self) -> int:
        raise NotImplementedError

    def extra_runs_per_cell(self) -> int:
        return 0

    def extra_sim_seconds_per_cell(self) -> float:
        return 0.0


def finder_runner(job: Finder, compute: Compute) -> RunFn:
    """The finder's `run` (the contract's `RunFn`, what `find` takes): each round's runs as
    tasks through the shared cache, each run's spec composed as the core's finder composes it
    (`probe_task`: the job's run template, a cell's mass and slope and a probe's start and
    length on top; so a run with the default numerics has the key `reproduce`'s finder gives
    it); progress as the share of the job's estimated simulated time done, moving inside a
    round too, never back, at most `CAP`."""
    budget = max(job.total_sim_seconds(), 1e-9)
    done = 0.0
    shown = ChunkProgress(compute.progress, runs=1)  # only its monotone, capped `show`
    params = job.model_params()
    template = job.template()

    def run(batch: list[tuple[Cell, Probe]]) -> list[dict[str, Any]]:
        nonlocal done
        tasks = [sim_core.run_task(template.spec(**p.spec_fields(), **c.spec_fields()), params)
                 for c, p in batch]  # fmt: skip
        asked, before = sum(p.duration_s for _, p in batch), done
        results = compute.run(tasks, lambda f: shown.show((before + f * asked) / budget))
        # what `find` reads of a run (`fixedpoints._run_of`): its Delta31 series, its error
        # and how long it ran (less than asked where it stopped settled)
        done += sum(
            r.get("duration_s") or p.duration_s for (_, p), r in zip(batch, results, strict=True)
        )
        shown.show(done / budget)
        return results

    return run


def finder_rows(cells: list[CellResult]) -> list[dict[str, Any]]:
    """One row per point the finder reports: stable, unstable, ghost or not settled."""
    rows: list[dict[str, Any]] = []
    for c in cells:
        base = {"beta": c.beta, "body_mass_g": c.body_mass_g, "slope_deg": c.slope_deg}
        for a in c.attractors:
            kind = "stable" if a.stable else "one-sided"
            rows.append(base | {"kind": kind, "d31": a.d31, "gait": a.gait,
                                "starts": a.starts, "slope": a.slope,
                                "drift": a.max_drift})  # fmt: skip
        for b in c.borders:
            rows.append(base | {"kind": "unstable", "d31": b.d31, "gait": None, "starts": None,
                                "slope": b.slope, "drift": None})  # fmt: skip
        for g in c.ghosts:
            rows.append(base | {"kind": "ghost", "d31": g.d31, "gait": None, "starts": None,
                                "slope": None, "drift": g.drift})  # fmt: skip
        for u in c.unsettled:
            rows.append(base | {"kind": "not settled", "d31": u.final, "gait": None,
                                "starts": None, "slope": None, "drift": u.drift})  # fmt: skip
    return rows


FINDER_MARKERS = {  # kind -> (marker, face colour, label)
    "stable": ("o", "k", "stable (settled runs)"),
    "unstable": ("o", "w", "unstable (basin border)"),
    "one-sided": ("o", "0.7", "settled, kicks return from one side only"),
    "ghost": ("x", "tab:red", "ghost (slowest passage)"),
    "not settled": ("v", "0.6", "not settled"),
}


def draw_finder_points(ax: Axes, records: list[dict[str, Any]]) -> None:
    """The finder's rows against beta: stable, unstable, ghosts, unsettled finals."""
    for kind, (marker, face, label) in FINDER_MARKERS.items():
        pts = [(r["beta"], r["d31"]) for r in records if r["kind"] == kind and r["d31"] is not None]
        if pts:
            edge = "k" if marker == "o" else face
            xs, ys = [p[0] for p in pts], [p[1] for p in pts]
            ax.scatter(xs, ys, s=22, marker=marker, facecolors=face, edgecolors=edge, label=label)

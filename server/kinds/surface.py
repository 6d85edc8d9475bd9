"""`surface`: the drift surface over a beta grid (`sim_core.paper.surface.drift_surface`, the
function `insect-gait surface` and `surface-check` use): the drift of Delta31 per gait cycle
at every held Delta31, its zeros (gaits, stable and unstable), near-zero bands and folds."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field, ValidationInfo, field_validator

import sim_core
from server.kinds.base import BetaRange, Kind, Physics, Result, Row
from server.kinds.bounds import bounded, core_bounds, core_default
from server.kinds.compute import Compute
from sim_core.contract import DriftSurface, SurfaceConfig, pin_problem, surface_grid

if TYPE_CHECKING:
    from matplotlib.figure import Figure

DEFAULT = SurfaceConfig()
GRID_ENDS = (min(DEFAULT.d31_grid), max(DEFAULT.d31_grid))
GRID_STEP = round(DEFAULT.d31_grid[1] - DEFAULT.d31_grid[0], 6)


class SurfaceRow(Row):
    """One probe, zero or near-zero band of the surface."""

    beta: float = Field(description="duty factor")
    kind: Literal["probe", "zero", "near_zero"] = Field(description="what the row is")
    pin_d31: float | None = Field(description="a probe's held Delta31, rad")
    d31: float | None = Field(
        description="Delta31 sampled (a probe), where the drift crosses zero (a zero), or a "
        "band's middle, rad"
    )
    drift: float | None = Field(description="drift per gait cycle, rad (a band: its least)")
    drift_se: float | None = Field(description="a probe's drift's standard error, rad")
    stable: bool | None = Field(description="a zero: stable")
    resolved: bool | None = Field(description="a zero: resolved; a band: false")
    why: str = Field(description="why a probe is not usable, or a band's extent")


class Held(Physics):
    """What every kind built on the drift surface asks (`surface`, `atlas`): the held Delta31
    grid, the pin's gain and whether to refine; resets must stay on (the pin needs them)."""

    d31_lo: float = bounded(GRID_ENDS[0], "d31_lo", "lowest held Delta31, rad", ge=0.5, le=6.0)
    d31_hi: float = bounded(GRID_ENDS[1], "d31_hi", "highest held Delta31, rad", ge=0.6, lt=6.2832)
    d31_step: float = bounded(
        GRID_STEP, "d31_step", "spacing of the held Delta31 values, rad", ge=0.01, le=1.0
    )
    gain_per_s: float = bounded(
        core_default("pin_gain_per_s"),
        "gain_per_s",
        "the pin's gain K, 1/s",
        **core_bounds("pin_gain_per_s"),
    )
    refine: bool = Field(
        True,
        description="bisect every zero's bracket and every dip of the drift, then probe finer "
        "and longer inside every unresolved zero and near-zero band, as `insect-gait surface` "
        "does; these probes are not in the size estimate (typically 30-60% more simulated "
        "time)",
    )

    @field_validator("phase_reset")
    @classmethod
    def _resets_on(cls, v: bool) -> bool:
        problem = pin_problem(DEFAULT.d31_grid[0], v)  # the core's words (RunSpec.pin_d31)
        if problem:
            raise ValueError(problem)
        return v

    @field_validator("d31_hi")
    @classmethod
    def _above_lo(cls, v: float, info: ValidationInfo) -> float:
        lo = info.data.get("d31_lo")
        if lo is not None and v <= lo:
            raise ValueError(f"d31_hi ({v:g}) must be above d31_lo ({lo:g})")
        return v

    def config(self) -> SurfaceConfig:
        from dataclasses import replace

        return replace(
            DEFAULT,
            d31_grid=surface_grid(self.d31_lo, self.d31_hi, self.d31_step),
            gain_per_s=self.gain_per_s,
        )

    def sim_seconds_per_run(self) -> float:
        return DEFAULT.duration_s


class SurfaceJob(Held):
    """The drift surface: walks held at each Delta31 by a weak pin on the fore and
    hind oscillators, resets on; per probe the drift per gait cycle with its standard error,
    per beta the zeros and near-zero bands, over beta the stable branches and folds."""

    kind: Literal["surface"] = "surface"
    beta_range: BetaRange

    def run_count(self) -> int:
        return self.beta_range.steps * len(self.config().d31_grid)


class SurfaceJobResult(Result):
    """A surface job's result: the core's typed surface and one row per probe and zero."""

    kind: Literal["surface"] = "surface"
    records: list[SurfaceRow]
    surface: DriftSurface = Field(description="the drift surface over the beta grid")


def run(job: SurfaceJob, compute: Compute) -> SurfaceJobResult:
    """The surface by the core's `drift_surface` on the job's run template (so every field of
    the job reaches every probe), its probes through the shared cache (the
    same keys as `insect-gait surface`'s, so either reads the other's back), refined
    (`refine`) as `insect-gait surface` refines it, with flat rows: one per probe, zero and
    near-zero band. Progress moves inside each chunk of probes run here (`ChunkProgress`)."""
    moving = compute.moving(job.run_count())
    s = sim_core.drift_surface(
        job.beta_range.values(), config=job.config(), params=job.model_params(),
        template=job.template(), refine=job.refine, progress=False,
        on_progress=moving.on_progress, **compute.core(moving),
    )  # fmt: skip
    rows: list[dict[str, Any]] = [
        {
            "beta": p.beta,
            "kind": "probe",
            "pin_d31": p.pin_d31,
            "d31": p.d31,
            "drift": p.drift,
            "drift_se": p.drift_se,
            "stable": None,
            "resolved": None,
            "why": p.why,
        }
        for p in s.points
    ]
    rows += [
        {
            "beta": z.beta,
            "kind": "zero",
            "pin_d31": None,
            "d31": z.d31,
            "drift": 0.0,
            "drift_se": None,
            "stable": z.stable,
            "resolved": z.resolved,
            "why": "",
        }
        for z in s.zeros
    ]
    rows += [
        {
            "beta": n.beta,
            "kind": "near_zero",
            "pin_d31": None,
            "d31": 0.5 * (n.lo + n.hi),
            "drift": n.min_abs_drift * n.sign,
            "drift_se": None,
            "stable": None,
            "resolved": False,
            "why": f"|drift| inside the noise floor from {n.lo:.3f} to {n.hi:.3f}",
        }
        for n in s.near_zeros
    ]
    return SurfaceJobResult(surface=s, records=rows)


def draw(fig: Figure, spec: dict[str, Any], result: dict[str, Any]) -> None:
    """The drift per cycle against the sampled Delta31, one curve per beta, zeros marked
    (stable solid, unstable open)."""
    ax = fig.add_subplot()
    rows = result.get("records", [])
    for b in sorted({r["beta"] for r in rows}):
        pts = sorted(
            (r["d31"], r["drift"])
            for r in rows
            if r["beta"] == b
            and r["kind"] == "probe"
            and r["d31"] is not None
            and r["drift"] is not None
        )
        if pts:
            (line,) = ax.plot(
                [x for x, _ in pts], [1e3 * y for _, y in pts], lw=1, label=f"β {b:g}"
            )
            for z in (r for r in rows if r["beta"] == b and r["kind"] == "zero"):
                ax.plot(
                    z["d31"],
                    0.0,
                    "o",
                    color=line.get_color(),
                    mfc=line.get_color() if z["stable"] else "white",
                )
    ax.axhline(0.0, color="grey", lw=0.8)
    ax.set_xlabel("Δ31 sampled at leg-1 touchdown (rad)")
    ax.set_ylabel("drift per gait cycle (mrad)")
    ax.set_title("drift surface: zeros are gaits (filled: stable, open: unstable)")
    ax.grid(alpha=0.3)
    if rows:
        ax.legend(fontsize="small")


KIND = Kind(model=SurfaceJob, run=run, result=SurfaceJobResult, row=SurfaceRow, draw=draw)

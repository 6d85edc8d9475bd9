"""The drift surface's protocol and its result's schema (`sim_core.paper.surface` computes it),
light enough for the edges: the REST kind validates and prices a job, and the viewer validates
a surface file, without loading the physics engine."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, fields
from typing import Any

from pydantic import BaseModel, ConfigDict, SerializerFunctionWrapHandler, field_serializer

from sim_core.contract.choice import Leaf
from sim_core.contract.finder import CLUSTER_TOL, FinderConfig
from sim_core.contract.values import METACHRONAL_BRANCH, TRIPOD_BRANCH
from sim_core.model.spec import PIN_GAIN_PER_S


def grid(lo: float, hi: float, step: float) -> tuple[float, ...]:
    """lo, lo + step, ..., hi (inclusive, rounded to 1e-6 so the task keys are stable)."""
    n = round((hi - lo) / step)
    return tuple(round(lo + k * step, 6) for k in range(n + 1))


@dataclass(frozen=True)
class SurfaceConfig:
    """The probes' protocol: chosen from measurement (docs/studies/journal.md, "The drift
    surface"; shared/notes/drift-surface.md for the first measurements)."""

    # K = 30 per s settles in about a gait cycle (K T ~ 3) and agrees with K = 10 within
    # 0.3 mrad per cycle; K >= 100 biases the 2.3-2.6 band by 1-2 mrad
    gain_per_s: float = PIN_GAIN_PER_S
    # touchdowns before this are skipped, drift is averaged over the next `average_s`: against
    # the 1 s + 2 s probe (itself within 0.06-0.1 mrad of a 24 s reference), 0.5 s + 1 s reads
    # the same drift within 0.05 mrad (median) and 0.2 mrad (90%) over 1,050 probes at half
    # the cost (docs/NUMERICS.md, "The drift surface's cost and precision")
    settle_s: float = 0.5
    average_s: float = 1.0
    block_s: float = 0.5  # the standard error comes from the scatter of these windows' drifts
    # below this a drift is zero within the pin's own bias (0.1-0.3 mrad per cycle at K 30)
    floor_rad: float = 3e-4
    # a probe whose sampled Delta31 spreads more than this over the averaging window did not
    # walk a periodic orbit: kept, not used for zeros
    periodic_tol_rad: float = 0.02
    # a probe whose sampled Delta31 left D by more than this (fore legs landing late, D <= 1.5)
    # is kept, not used for zeros: it measures somewhere else than the grid says
    off_pin_tol_rad: float = 0.1
    # the first pass: 0.1 rad apart; bisection then probes 0.05 apart only near zeros and dips
    # of |d| (a first pass 0.1 apart with no bisection missed the metachronal pair 1.74 / 1.81
    # at beta 0.66, hidden between 1.7 and 1.8; with it, every fold of the 0.05 grid is found)
    d31_grid: tuple[float, ...] = field(default_factory=lambda: grid(1.3, 3.5, 0.1))
    # a zero is resolved when floor-clearing probes of opposite sign bracket it this closely
    # and the drift crosses zero once between them
    resolve_width_rad: float = 0.05
    # rounds of bisection (`surface.bisection_probes`) inside every zero's bracket and beside
    # every dip of |d|, each halving the spacing there: two take 0.1 to 0.05 and catch a zero
    # the first round uncovers
    bisect_rounds: int = 2
    # the last pass (`surface.refinement_probes`): inside every unresolved bracket and
    # near-zero band, probes this far apart, averaged this long (2.5 s: 1.6x fewer standard
    # errors than the first pass's 1 s window)
    refine_step: float = 0.02
    refine_average_s: float = 2.5
    # whether that last pass runs: it resolves narrow pairs (the tripod near 2.93) and costs
    # 40% of Fig. 8; an atlas, which asks only which gaits have a stable zero, may skip it
    # and mark such cells unresolved
    band_pass: bool = True
    link_tol_rad: float = 0.12  # a stable zero continues a branch at the next beta within this
    chunk_size: int = 8

    @property
    def duration_s(self) -> float:
        return self.settle_s + self.average_s

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


# Short probes (issue 54): settle 0.25 s (not 0.5) and average 0.5 s (first pass, bisection;
# not 1 s) and 1.5 s (the last pass; not 2.5 s). Read from the same runs of the longer
# protocol, the drift moved by 0.075 mrad per cycle (median of 766 probes; 11% beyond the
# 0.3 mrad floor, no sign flipped beyond it) and 0.05 (349 last-pass probes; 4%, one sign),
# below the physics step's own 2.4 mrad (dt/2): a pinned walk started on its family member D
# has settled by 0.2 s (docs/NUMERICS.md, "Reproduce within 5 minutes"). `reproduce` uses
# them. Not valid in the soft-leg regime: there they move the drift by 0.36 mrad (median of
# 271 probes, 60% beyond the floor, 7 signs flipped; `python -m lab.campaigns.short_probes`).
SHORT_PROBES = SurfaceConfig(settle_s=0.25, average_s=0.5, block_s=0.25, refine_average_s=1.5)

# Starts near the paper's branches (Fig. 5): the metachronal at 1.9, the tripod from 3.0, not
# 2.9: at beta 0.62 the tripod's basin border sits at 2.88-2.91 (finder 2.884, surface's
# unstable zero 2.913), so a start at 2.9 would test the saddle, not the branch.
PAPER_STARTS = (METACHRONAL_BRANCH, TRIPOD_BRANCH + 0.1)


@dataclass(frozen=True)
class WalkConfig:
    """How an atlas cell's open spans are walked (`sim_core.paper.surface_walks`)."""

    # the finder's lengths (`FinderConfig`): a try that stops if settled by then, else runs on
    try_s: float = FinderConfig().bisect_duration_s
    duration_s: float = FinderConfig().duration_s
    # starts this far outside a span: a span's ends are probes whose drift already cleared the
    # noise floor, and a free run's first cycles wander by ~0.01-0.02 rad from its start
    margin_rad: float = 0.03
    # starts closer than this are one walk (the finder's "one attractor" distance)
    merge_rad: float = CLUSTER_TOL
    paper_starts: tuple[float, ...] = PAPER_STARTS


@dataclass(frozen=True)
class SurfaceAtlasConfig(SurfaceConfig):
    """A surface atlas's protocol as it records it: its surfaces' (`SurfaceConfig`), whether
    they were refined, and how its cells were walked (None: not walked; then left out of the
    file, as atlases without walks were written)."""

    refine: bool = True
    walks: WalkConfig | None = None
    # whether each cell was also walked from the paper's start of every gait a neighbouring
    # cell holds and it lacks (`surface_walks.neighbour_rounds`); left out of the file when
    # not, as atlases written before it were
    neighbour_walks: bool = False

    @classmethod
    def of(
        cls,
        config: SurfaceConfig,
        *,
        refine: bool,
        walks: WalkConfig | None,
        neighbour_walks: bool = False,
    ) -> SurfaceAtlasConfig:
        """The atlas's record of its surfaces' protocol `config`, refined or not, walked so."""
        shared = {f.name: getattr(config, f.name) for f in fields(SurfaceConfig)}
        return cls(**shared, refine=refine, walks=walks, neighbour_walks=neighbour_walks)


class _Model(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")


class SurfacePoint(_Model):
    """One pinned probe at (beta, D)."""

    beta: float
    pin_d31: float  # D, rad
    d31: float | None  # Delta31 sampled after leg-1 touchdowns (circular mean), rad
    spread: float | None  # max |sample - mean| over the averaging window, rad
    drift: float | None  # rad per gait cycle, 1/4 [(e5 + e6) - (e1 + e2)]
    drift_se: float | None  # its standard error from `SurfaceConfig.block_s` windows, rad
    jumps: list[float | None]  # mean e1..e6, rad (e > 0: the leg landed early)
    cycles: int  # leg-1 touchdowns averaged
    usable: bool  # periodic, near its pin, not failed: used for zeros
    why: str = ""  # why not usable


class SurfaceZero(_Model):
    """A zero of d at one beta."""

    beta: float
    d31: float  # where the raw drift crosses zero (if once), else the bracket's middle, rad
    lo: float  # the bracket: the probes on either side, rad
    hi: float
    stable: bool  # d falls through zero as Delta31 rises
    slope: float | None  # dd / dDelta31, the secant over the bracket; return map 1 + 4 slope
    resolved: bool


class NearZero(_Model):
    """A band where |d| stays inside the noise floor and returns to its sign: a tangency, a
    ghost, or a narrow pair of zeros the surface cannot separate."""

    beta: float
    lo: float
    hi: float
    sign: int  # the sign of d on both sides
    min_abs_drift: float  # the smallest |d| in the band, rad per cycle


class Branch(_Model):
    """Stable zeros linked across neighbouring betas (each within `link_tol_rad`)."""

    betas: list[float]
    d31: list[float]
    resolved: list[bool]


class Fold(_Model):
    """Where a stable branch ends between two grid betas (resolution: their distance)."""

    beta_lo: float
    beta_hi: float
    d31: float  # the branch's last value, rad
    side: str  # "ends as beta rises" or "ends as beta falls"
    resolution: float  # beta_hi - beta_lo
    resolved: bool  # the branch's last zero was resolved


class DriftSurface(_Model):
    """The drift surface over betas x D, with what it says."""

    config: SurfaceConfig  # the probes' protocol (a key absent from an old file: its default)
    betas: list[float]
    points: list[SurfacePoint]
    zeros: list[SurfaceZero]
    near_zeros: list[NearZero]
    branches: list[Branch]
    folds: list[Fold]
    sim_s: float  # simulated seconds behind it
    body_mass_g: float
    slope_deg: float
    ground: str
    # the model's leaves off their defaults its probes ran with (`changed_leaves`; the ground
    # is `ground`): empty for the defaults, as in every file written before they were recorded
    params: dict[str, Leaf] = {}
    setting: str | None = None  # the named setting they came from, where an edge named one

    def zeros_at(self, beta: float) -> list[SurfaceZero]:
        return [z for z in self.zeros if abs(z.beta - beta) < 1e-9]

    def points_at(self, beta: float) -> list[SurfacePoint]:
        return [p for p in self.points if abs(p.beta - beta) < 1e-9]

    def curve_at(self, beta: float) -> list[SurfacePoint]:
        """The usable probes at `beta` in order of sampled Delta31: the curve d(Delta31)."""
        usable = (p for p in self.points_at(beta) if p.usable and p.d31 is not None)
        return sorted(usable, key=lambda p: float(p.d31 or 0.0))


# an atlas cell's region (`region`) and its colour (matplotlib names)
REGION_COLOURS = {
    "both": "tab:purple",
    "tripod only": "tab:red",
    "metachronal only": "tab:blue",
    "other states": "0.6",
    "none": "white",
}


def region(gaits: Sequence[str]) -> str:
    """An atlas cell's region from its stable states' gaits: which of the paper's two gaits
    are among them."""
    g = set(gaits)
    if {"tripod", "metachronal"} <= g:
        return "both"
    if "tripod" in g:
        return "tripod only"
    if "metachronal" in g:
        return "metachronal only"
    return "other states" if g else "none"


class AtlasWalk(_Model):
    """A free walk that decided an atlas cell (`surface_walks`), read by `gait.settling`."""

    start: float  # Delta31 it started from, rad
    final: float | None  # where it ends (last quarter's circular mean), rad
    settled: bool
    why: str  # why not settled ("" if settled), or the run's failure
    sim_s: float  # simulated seconds it took (it stops early where settled)
    # a neighbour walk (`surface_walks.neighbour_rounds`) that did not settle but has left the
    # gait it started in for one its cell holds already: wherever it settles there, the region
    # stays, so it does not leave the cell undecided
    left_gait: bool = False


class AtlasPoint(_Model):
    """One (beta, axis value) of a surface atlas: its stable states in the window and what
    they make of the paper's two gaits."""

    beta: float
    value: float
    stable: list[float]  # stable states' Delta31, rad: the surface's zeros, then walks' finals
    gaits: list[str]  # classify_gait of each
    unresolved: int  # zeros or near-zero bands the surface could not resolve here
    region: str  # "both", "tripod only", "metachronal only", "other states", "none"
    # per stable state: "surface" (a stable zero), "walk" (a settled walk's final only) or
    # "surface+walk"; empty in atlases written before the walks (all "surface")
    provenance: list[str] = []
    walks: list[AtlasWalk] = []  # the walks this cell needed (`surface_walks.open_spans`)
    checked: bool = False  # whether the cell went through `surface_walks.decide`

    @property
    def undecided(self) -> bool:
        """Whether the cell's region may hide a gait: a walk did not settle, or (in an atlas
        not checked by walks) the surface left a zero or band unresolved."""
        if self.checked:
            return any(not w.settled and not w.left_gait for w in self.walks)
        return self.unresolved > 0


class SurfaceAtlas(_Model):
    """Drift surfaces over beta at each value of body mass (g) or slope (deg): which gaits are
    stable where, and where their branches fold."""

    axis: str  # "mass" or "slope"
    param: str  # the RunSpec field: body_mass_g or slope_deg
    ground: str
    betas: list[float]
    values: list[float]
    points: list[AtlasPoint]  # value-major
    folds: list[tuple[float, Fold]]  # (axis value, fold over beta at that value)
    sim_s: float
    config: SurfaceAtlasConfig
    params: dict[str, Leaf] = {}  # as DriftSurface's: the model's leaves off their defaults
    setting: str | None = None

    @field_serializer("config", mode="wrap")
    def _walks_only_if_walked(
        self, config: SurfaceAtlasConfig, handler: SerializerFunctionWrapHandler
    ) -> Any:
        out = handler(config)
        if isinstance(out, dict) and out.get("walks") is None:
            out.pop("walks", None)
        if isinstance(out, dict) and not out.get("neighbour_walks"):
            out.pop("neighbour_walks", None)
        return out

    @property
    def regions(self) -> list[list[str]]:
        """regions[i][j]: the region at values[i], betas[j] (`points` is value-major)."""
        nb = len(self.betas)
        return [
            [p.region for p in self.points[i * nb : (i + 1) * nb]] for i in range(len(self.values))
        ]

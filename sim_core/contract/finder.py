"""The fixed-point finder's protocol and typed output, and its gait atlas's: what `reproduce`,
the REST `bifurcation`, `finder` and `atlas` kinds, the lab and the viewer read and validate,
without the engine (the search that fills them: `sim_core.paper.finder.find`, which asks its
caller's `RunFn` for the runs).

A condition (`Cell`) is searched with runs (`Probe`) as `FinderConfig` says; what the finder
knows about it is a `CellResult`: stable gaits (`Attractor`), the borders between their basins
(`Border`, the unstable gaits), slow passages (`Ghost`) and every run (`RunOutcome`).
`FinderOutput` is one finder run over many conditions (bifurcation.json); `AtlasOutput` the
finder over a beta x (mass | slope) grid (atlas_<axis>.json).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    SerializerFunctionWrapHandler,
    model_serializer,
)

from sim_core.contract.choice import Leaf
from sim_core.contract.results import AtlasAxis

# Settled finals closer than this (rad) are one attractor: 10x the spread of a settled tail
# (1-4 mrad measured) and 4x below the closest pair of distinct states seen (2.12 / 2.27 at
# beta 0.62).
CLUSTER_TOL = 0.05


@dataclass(frozen=True)
class FinderConfig:
    """How hard the finder looks; each choice measured (docs/NUMERICS.md, "The finder")."""

    starts: int = 8  # spread over the circle (`initial_values`), 0.79 rad apart
    # Measured (beta 0.62-0.70, 8 starts, 40 s): attractors settle (< 0.2 mrad per cycle)
    # within 13-30 s; a tripod start at beta 0.655 sits 15-20 s on its ghost at 2.97 with
    # < 0.05 mrad per cycle before it slides (so 20 s calls it settled, 40 s does not).
    duration_s: float = 40.0
    # Bisection runs only decide a basin between two known attractors; one that has not
    # settled by then goes on to `duration_s` (`Probe.stop_if_settled_s`: one run, not a
    # short try and a re-run from the start).
    bisect_duration_s: float = 20.0
    border_tol_rad: float = 0.02  # the bracket of a border's starts
    # At most this many borders per condition, preferring those in the paper's window: each
    # costs ~6 runs (0.79 -> 0.02 rad).
    max_borders: int = 2
    # Borders are bisected between attractors of different gaits only (classify_gait);
    # two settled states of one gait (e.g. 1.77 / 2.12 at 0.62) are both listed, unbisected.
    window: tuple[float, float] = (1.4, 3.4)  # PAPER_WINDOW
    # Each state is re-run from this far on either side (bisect_duration_s, on to duration_s
    # if unsettled) and is stable only if both come back within CLUSTER_TOL: the issue's
    # "reached from near it" made two-sided. 0.03: a tenth of the smallest basin measured
    # (2.88-2.95 at 0.62 is 0.07 wide; closer saddles shrink the kick, KICK_ROOM). 0: no
    # kicks; every state is then reported as "not checked" (the atlas, to stay in budget).
    kick_rad: float = 0.03
    # Neighbouring betas (same mass and slope) lend the states they found and this beta did
    # not, as extra starts: the state itself and the starts that reached it there. A state with
    # a thin basin that this beta's spread starts miss (4.58 at 0.655, reached at 0.65 from a
    # bisection start 0.59 and at 0.66 from 5.89) is then looked for where it should be.
    neighbour_seeds: bool = True

    @classmethod
    def quick(cls) -> FinderConfig:
        """The machinery on short runs (tests, --quick): nothing here settles by the rule."""
        return cls(starts=3, duration_s=1.5, bisect_duration_s=1.0, border_tol_rad=0.4,
                   max_borders=1, kick_rad=0.0, neighbour_seeds=False)  # fmt: skip


@dataclass(frozen=True)
class Cell:
    """One condition: beta and the physics a RunSpec takes besides the start."""

    beta: float
    body_mass_g: float = 3.0
    slope_deg: float = 0.0
    # extra starts beside the spread ones: where neighbouring conditions found attractors (the
    # atlas), since a start near an attractor that still exists settles at once
    seeds: tuple[float, ...] = ()

    def spec_fields(self) -> dict[str, float]:
        return {"beta": self.beta, "body_mass_g": self.body_mass_g, "slope_deg": self.slope_deg}


@dataclass(frozen=True)
class Probe:
    """One run a search asks for: a start and a duration, at its cell's condition; with
    `stop_if_settled_s`, a short try that runs on to `duration_s` only if it has not settled
    by then (`RunSpec.stop_if_settled_s`: the same numbers as a short run and its re-run)."""

    d31_init: float
    duration_s: float
    stop_if_settled_s: float | None = None

    def spec_fields(self) -> dict[str, float | None]:
        """The RunSpec fields of this run besides its cell's (`Cell.spec_fields`)."""
        return {"d31_init": self.d31_init, "duration_s": self.duration_s,
                "stop_if_settled_s": self.stop_if_settled_s}  # fmt: skip


# What the search asks of its caller: (cell, probe) pairs in, one result dict per pair out with
# the task result's keys (`d31`, `error`, and `duration_s` where a run stopped settled).
RunFn = Callable[[list[tuple[Cell, Probe]]], list[dict[str, Any]]]


# --- the output schema (what reproduce, the REST kinds and the viewer read) --------------------
# A file written before an option existed ran without it: its protocol reads as the option's
# "off", not today's default (docs/figures/atlas_mass.json and atlas_slope.json were searched
# before states were kicked or neighbours lent seeds; their states are "not checked").
BEFORE_THE_OPTION: dict[str, Any] = {"kick_rad": 0.0, "neighbour_seeds": False}


def _as_it_ran(value: Any) -> Any:
    """A recorded protocol (a JSON object) with the options it predates off."""
    return BEFORE_THE_OPTION | value if isinstance(value, dict) else value


# The finder's protocol as an output records it: a `FinderConfig`, read as it ran.
RecordedFinderConfig = Annotated[FinderConfig, BeforeValidator(_as_it_ran)]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


Role = Literal["start", "seed", "bisect", "kick"]
# How a state's kicks came back: from both sides (stable), from one side only (it attracts
# from below or above only: semi-stable, or the edge of a slowly drifting band), from neither
# (only its own start reached it), or not kicked (FinderConfig.kick_rad = 0).
Confirmed = Literal["both sides", "below only", "above only", "neither", "not checked"]


class RunOutcome(_Model):
    """One settled-or-not run of the search."""

    d31_init: float
    duration_s: float  # asked for (the probe's)
    final: float | None  # circular mean of the last quarter (rad)
    drift: float | None  # rad per gait cycle over the last quarter
    settled: bool
    why: str  # why not settled ("" if settled)
    attractor: int | None  # index into CellResult.attractors, None if unsettled or failed
    failure: str | None = None
    role: Role = "start"
    stop_if_settled_s: float | None = None  # the probe's short try, if it had one
    simulated_s: float | None = None  # how long it ran: less than duration_s if it stopped

    def probe(self) -> Probe:
        """The probe that ran it (its task, `sim_core.paper.search.probe_task`, reads its series
        back)."""
        return Probe(self.d31_init, self.duration_s, self.stop_if_settled_s)


class Attractor(_Model):
    """A stable gait: where settled runs end (finals within CLUSTER_TOL)."""

    d31: float  # circular mean of its runs' finals, rad
    lo: float  # lowest and highest final (a spread > 0 is a flat band, or slow drift)
    hi: float
    gait: str  # classify_gait of d31
    starts: int  # how many of the spread starts end here (seeds not counted)
    runs: int  # all runs that end here (starts and bisection)
    slope: float | None  # of the n -> n+4 map at it, from its runs' approach (< 1: attracts)
    slope_pairs: int
    max_drift: float  # largest |drift| per cycle of its runs' settled tails
    confirmed: Confirmed = "not checked"
    kicks: tuple[float, float] | None = None  # the kicks' sizes below and above, rad

    @property
    def stable(self) -> bool:
        """A stable gait: its kicks came back from both sides, or it was not kicked."""
        return self.confirmed in ("both sides", "not checked")


class Border(_Model):
    """An unstable gait: the border between two basins, by bisection of the start."""

    below: int  # attractor reached from the lower start of the bracket
    above: int  # ... from the upper start
    start_lo: float  # the bracket of starts, rad (start_hi may exceed 2 pi: on the circle)
    start_hi: float
    resolved: bool  # bracket narrower than the finder's border_tol_rad
    d31: float | None  # where the bracketing runs dwell before they part (the saddle), rad
    slope: float | None  # growth of their separation per 4 cycles (> 1: repels)
    steps: int  # bisection runs made
    note: str = ""


class Ghost(_Model):
    """A slowest passage: a run slides on through here, slowly."""

    d31: float
    drift: float  # rad per cycle at the slowest point (signed)
    cycles: int  # cycles the run spent within CLUSTER_TOL of it
    d31_init: float  # the run that shows it


class CellResult(_Model):
    """Everything the finder knows about one condition."""

    beta: float
    body_mass_g: float
    slope_deg: float
    attractors: list[Attractor]
    borders: list[Border]
    ghosts: list[Ghost]
    runs: list[RunOutcome]
    sim_s: float  # simulated seconds spent

    @property
    def unsettled(self) -> list[RunOutcome]:
        """Runs that did not settle and were not re-run longer from the same start (a short
        try that was re-run longer is a screen, not a finding; since the finder's tries go on
        in one run, `Probe.stop_if_settled_s`, this matters for outputs written before)."""
        longest: dict[tuple[float, str], float] = {}
        for r in self.runs:
            key = (r.d31_init, r.role)
            longest[key] = max(longest.get(key, 0.0), r.duration_s)
        return [
            r
            for r in self.runs
            if not r.settled and r.failure is None and r.duration_s >= longest[(r.d31_init, r.role)]
        ]

    def stable(self, gait: str | None = None) -> list[Attractor]:
        """The stable states (`Attractor.stable`), of one gait if given."""
        return [a for a in self.attractors if a.stable and (gait is None or a.gait == gait)]

    def one_sided(self) -> list[Attractor]:
        """Settled states that kicks did not confirm from both sides."""
        return [a for a in self.attractors if not a.stable]

    def pattern(self, window: tuple[float, float] = (1.4, 3.4)) -> str:
        """'S U S'-style, in order of Delta31 inside `window`: the paper's Fig. 7 reading."""
        pts = [(a.d31, "S") for a in self.stable()]
        pts += [(b.d31, "U") for b in self.borders if b.d31 is not None]
        return " ".join(s for x, s in sorted(pts) if window[0] <= x <= window[1])


class FinderOutput(_Model):
    """The finder over a set of conditions: the one data file Figs. 7-8, the REST
    `bifurcation` and `atlas` kinds and the viewer's panels read. A file made with other than
    the defaults records how (`insect-gait finder`'s model and run flags): its ground, named
    setting, model leaves and run fields off their defaults; a default file has none of them
    (they are left out of its JSON, so it reads as it was written)."""

    source: str
    config: RecordedFinderConfig
    cells: list[CellResult]
    ground: str | None = None  # None: the core's default ground
    setting: str | None = None
    params: dict[str, Leaf] = {}
    run: dict[str, Leaf] = {}  # RunSpec fields off their defaults, shared by every run

    @model_serializer(mode="wrap")
    def _provenance_only_if_made(self, handler: SerializerFunctionWrapHandler) -> Any:
        out = handler(self)
        if isinstance(out, dict):
            for k in ("ground", "setting", "params", "run"):
                if not out.get(k):
                    out.pop(k, None)
        return out


# --- the gait atlas's schema (`sim_core.paper.atlas` writes it; the REST kind and the viewer
# read it) ---------------------------------------------------------------------------------------
AXIS_PARAM: dict[str, str] = {"mass": "body_mass_g", "slope": "slope_deg"}
AXIS_LABEL: dict[str, str] = {"mass": "body mass (g)", "slope": "slope (deg, uphill +)"}
Region = Literal["both", "tripod only", "metachronal only", "other states", "not settled"]
REGIONS: tuple[str, ...] = ("both", "tripod only", "metachronal only", "other states",
                            "not settled")  # fmt: skip


def region_of(cell: CellResult) -> Region:
    """Which of the paper's two gaits are stable at one condition (classify_gait of each
    stable state); 'not settled' when no run settled at all."""
    gaits = {a.gait for a in cell.stable()}
    if "tripod" in gaits and "metachronal" in gaits:
        return "both"
    if "tripod" in gaits:
        return "tripod only"
    if "metachronal" in gaits:
        return "metachronal only"
    return "other states" if cell.attractors else "not settled"


class AtlasFold(_Model):
    """Where a gait's stable range along beta ends, at one value of the other axis."""

    gait: str
    value: float
    side: str  # "upper": the gait lives below this beta; "lower": above it
    beta: float
    half_width: float


class AtlasGrid(_Model):
    """What a finder atlas searched, as it records it: its grid and the finder's protocol."""

    betas: list[float]
    values: list[float]
    finder: RecordedFinderConfig


class AtlasOutput(_Model):
    """The finder over a beta x (body mass | slope) grid: regions, attractors, fold lines."""

    source: str
    axis: AtlasAxis
    param: str  # the RunSpec field of the axis: body_mass_g or slope_deg
    betas: list[float]
    values: list[float]
    cells: list[CellResult]  # value-major: cells[i * len(betas) + j] is (values[i], betas[j])
    regions: list[list[Region]]  # [value][beta]
    folds: list[AtlasFold]
    sweep_beta: float  # the paper's Fig. 9 sweeps run at this beta ...
    sweep_range: tuple[float, float]  # ... over this range of the axis (ours, `ReproduceConfig`)
    paper_direction: str
    config: AtlasGrid

    def cell(self, value_index: int, beta_index: int) -> CellResult:
        return self.cells[value_index * len(self.betas) + beta_index]

"""The fifth campaign's search (issue 40, point 2): every invented parameter at once, scored on
coarse drift surfaces.

Why a surface and not free runs: a surface reads, per beta, the whole stability landscape
(which gaits exist, where they sit) in ~130 pinned probes of 1.5 s, and the question the paper
asks is where each gait stops existing. A candidate's score is built from two continuous
margins per beta, read off the drift d(Delta31) of `OBJECTIVE_BETAS` x `OBJECTIVE_CONFIG`:
- the metachronal margin m_M = -min d over `METACHRONAL_SIDE` (> 0: the drift turns negative
  above the fore legs' wall, so a stable metachronal-side zero exists);
- the tripod margin m_T = max d over `TRIPOD_FEED` (> 0: the drift carries walks up into the
  tripod near 2.9-3.0 from below).
The paper has m_M < 0 below beta 0.645 and > 0 above, m_T > 0 below 0.67 and < 0 above; the
folds are where each margin crosses zero in beta (linear between the betas, extrapolated from
the nearest two when it does not cross inside them). The score adds the two fold errors (in
beta), the branch values' errors, extra stable zeros, and walking sanity (speed against eq. 2,
slip, landing share, probes that did not walk a periodic orbit).

The paper's values (Table I masses and lengths, D, T_sw, K) are never searched.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from lab.space import Range
from sim_core import Backend, ModelParams, ResultCache, drift_surface, nominal_speed, run_task
from sim_core.contract import (
    PARAMETER_NAMES,
    SHORT_PROBES,
    DriftSurface,
    SurfaceConfig,
    surface_grid,
)
from sim_core.research import grid_probes, probe_spec

# six betas around the paper's folds (0.645, 0.67), none on them; 0.62 and 0.70 are Fig. 5's
OBJECTIVE_BETAS = (0.62, 0.635, 0.655, 0.665, 0.685, 0.70)
# 21 D values 0.1 apart, one pass (no bisection): 126 probes x 1.5 s = 189 simulated s
OBJECTIVE_CONFIG = SurfaceConfig(d31_grid=surface_grid(1.4, 3.4, 0.1))
# the same probes at half the cost (issue 54): the short probes (0.25 s settle + 0.5 s,
# `SHORT_PROBES`), 126 x 0.75 = 94.5 simulated s; candidates' scores on both:
# `benchmarks/candidate_cost.py`, docs/NUMERICS.md. Campaign 5 keeps OBJECTIVE_CONFIG. Stiff
# regime only: in the soft one they move the drift by 0.36 mrad (`lab.campaigns.short_probes`).
FAST_OBJECTIVE_CONFIG = replace(SHORT_PROBES, d31_grid=OBJECTIVE_CONFIG.d31_grid)
PAPER_METACHRONAL_FOLD = 0.645  # the metachronal gait exists from here up (paper, Fig. 8)
PAPER_TRIPOD_FOLD = 0.67  # the tripod exists from here down
METACHRONAL_SIDE = (1.75, 2.6)  # where d turns negative above the fore wall when it holds
TRIPOD_FEED = (2.55, 2.95)  # where d must be positive to carry walks into the tripod
METACHRONAL_WINDOW = (1.55, 2.35)  # a stable zero here is the metachronal gait
TRIPOD_WINDOW = (2.7, 3.2)  # a stable zero here is the tripod
METACHRONAL_TARGET = 1.9  # the paper's branch values (Fig. 5)
TRIPOD_TARGET = 2.9
FOLD_CLIP = (0.55, 0.80)  # an extrapolated fold is clipped here
# score weights: fold errors in beta; a branch 0.1 rad off costs as much as a fold 0.01 off;
# every stable zero the paper does not have costs 0.01; walking badly costs more than a fold
BRANCH_WEIGHT = 0.1
EXTRA_ZERO_WEIGHT = 0.01
SANITY_WEIGHT = 0.5
UNUSABLE_SHARE_OK = 0.15  # above this share of non-periodic / failed probes, a penalty
FAILED_SCORE = 2.0  # a candidate that cannot be built or walked


# Every invented continuous parameter that can matter, with its range and reason (the
# campaigns' ranges widened where a study found the edge mattered); conditional ones below.
SPACE5: dict[str, Range] = {
    "com_offset_x": Range(-4e-3, 4e-3, False, "centre of mass within the thorax, +-4 mm"),
    "attach_x_fore": Range(7e-3, 13e-3, False, "fore coxae on the front third of the body"),
    "attach_x_hind": Range(-13e-3, -7e-3, False, "hind coxae on the rear third"),
    "attach_y": Range(3.5e-3, 6e-3, False, "coxae at or just inside the body's side"),
    "attach_z": Range(-1.5e-3, 1.5e-3, False, "coxae within the 4 mm thick body"),
    # the stance geometry in coordinates that keep every tip within the leg's reach (sampled
    # in the attachments' own terms, ~60% of random draws were out of reach; see `geometry`)
    "leg_span": Range(8.3e-3, 9.5e-3, False, "coxa to stance line: 8.1 folded, ~12 straight"),
    "leg_elevation_deg": Range(35.0, 60.0, False, "the stance line's angle below the coxa"),
    "stance_dx_fore": Range(0.5e-3, 4e-3, False, "fore tips ahead of the fore coxae"),
    "stance_x_mid": Range(-2e-3, 2e-3, False, "middle tips within 2 mm of their coxae"),
    "stance_dx_hind": Range(0.5e-3, 4e-3, False, "hind tips behind the hind coxae"),
    "apex_share": Range(0.1, 1.0, False, "swing apex as a share of the room under the coxa"),
    "landing_height_kept": Range(0.0, 1.0, False, "stance line from LP's place or height"),
    "late_swing_descent": Range(0.0, 0.9, False, "a late foot follows the line or reaches down"),
    "kp_yaw": Range(1.5e-3, 1.5e-2, True, "fore-aft stiffness, sag 0.003-0.03 rad"),
    "kp_lift": Range(1.5e-3, 8e-3, True, "lift stiffness, sag 0.05-0.3 mm (stiffer flips)"),
    "kd_yaw": Range(1e-5, 1.5e-4, True, "yaw time constants 1-30 ms at kp_yaw"),
    "kd_lift": Range(1e-6, 2e-5, True, "lift time constants 0.2-7 ms at kp_lift"),
    "support_ratio": Range(0.5, 2.0, True, "middle pair half to twice as stiff"),
    "velocity_feedforward_yaw": Range(0.5, 1.2, False, "yaw damping on the error or velocity"),
    "velocity_feedforward_lift": Range(0.0, 1.2, False, "lift damping: velocity to error"),
    "coxa_radius": Range(0.1e-3, 0.5e-3, False, "link radii: the inertia's radius term"),
    "femur_radius": Range(0.15e-3, 0.6e-3, False, "femur 0.3-1.2 mm thick"),
    "tibia_radius": Range(0.08e-3, 0.3e-3, False, "tibia 0.16-0.6 mm thick"),
    "friction": Range(0.7, 2.0, False, "claws and pads: smooth to rough ground"),
    "touch_depth": Range(3e-8, 1e-6, True, "touch threshold 1-30% of a leg's static load"),
    "scuff_fraction": Range(0.3, 0.7, False, "how early in swing a touch counts as landing"),
}
# searched only on the ground they belong to
CONSTRAINT_SPACE: dict[str, Range] = {
    "contact_timeconst": Range(2e-4, 2e-3, True, "stiff to moderately soft constraint contact"),
}
PENALTY_SPACE: dict[str, Range] = {
    "ground_stiffness": Range(800.0, 5000.0, True, "the paper's spring; 5000 at the step's edge"),
    "ground_damping": Range(0.03, 0.3, True, "0.1-1 of critical for a 10 mg tip"),
}
GROUNDS = ("constraint", "penalty")
# the closest a tip may come to its coxa attachment: the tibia (10 mm) folded back on the femur
# (2 mm, 2% margin as `calibrate.reachable`) and the coxa's 0.2 mm; the swing apex may rise
# until the tip is this close above the stance line's lateral place
FOLDED_REACH = 8.1e-3
COXA = 0.2e-3
MIN_APEX = 0.2e-3
MAX_APEX = 2.0e-3


def geometry(values: dict[str, float]) -> dict[str, float]:
    """`ModelParams` fields from the search's geometric coordinates (the rest passed through):
    leg span and elevation give the sprawl (foot_y - attach_y) and stand height; the stance
    lines sit stance_dx ahead of / behind their coxae; the swing apex is a share of the room
    between the stance line and the folded-leg limit above it."""
    v = dict(values)
    span, elev = v.pop("leg_span"), math.radians(v.pop("leg_elevation_deg"))
    sprawl, stand = span * math.cos(elev), span * math.sin(elev)
    room = stand - math.sqrt(max(0.0, FOLDED_REACH**2 - (sprawl - COXA) ** 2))
    v["foot_y"] = v["attach_y"] + sprawl
    v["stand_height"] = stand
    v["stance_x_fore"] = v["attach_x_fore"] + v.pop("stance_dx_fore")
    v["stance_x_hind"] = v["attach_x_hind"] - v.pop("stance_dx_hind")
    v["swing_height"] = min(MAX_APEX, max(MIN_APEX, v.pop("apex_share") * room))
    return v


def coordinates(p: ModelParams) -> dict[str, float]:
    """The search's coordinates of `p` (the inverse of `geometry`, for starting points)."""
    sprawl, stand = p.trajectory.foot_y - p.legs.attach_y, p.trajectory.stand_height
    room = stand - math.sqrt(max(0.0, FOLDED_REACH**2 - (sprawl - COXA) ** 2))
    out = {n: float(p.leaf(n)) for n in SPACE5 if n in PARAMETER_NAMES}
    return out | {
        "leg_span": math.hypot(sprawl, stand),
        "leg_elevation_deg": math.degrees(math.atan2(stand, sprawl)),
        "stance_dx_fore": p.trajectory.stance_x_fore - p.legs.attach_x_fore,
        "stance_dx_hind": p.legs.attach_x_hind - p.trajectory.stance_x_hind,
        "apex_share": p.trajectory.swing_height / room if room > 0 else 1.0,
    }


FRAMES = ("body", "level")


@dataclass
class SurfaceScore:
    """One candidate's reading of its coarse surface, and its score (lower is better)."""

    metachronal_margin: list[float | None]  # m_M per beta, rad per cycle
    tripod_margin: list[float | None]  # m_T per beta
    metachronal_fold: float  # beta where m_M crosses zero
    tripod_fold: float
    metachronal_value: float | None  # the metachronal zero at the highest beta
    tripod_value: float | None  # the tripod zero at the lowest beta
    extra_zeros: int  # stable zeros the paper does not have
    speed_ratio: float | None  # median measured / eq. 2 speed
    slip: float | None  # median slip share
    landing_share: float | None  # median landing share
    unusable_share: float
    parts: dict[str, float] = field(default_factory=dict)

    @property
    def metachronal_fold_error(self) -> float:
        return abs(self.metachronal_fold - PAPER_METACHRONAL_FOLD)

    @property
    def tripod_fold_error(self) -> float:
        return abs(self.tripod_fold - PAPER_TRIPOD_FOLD)

    @property
    def score(self) -> float:
        return float(sum(self.parts.values()))

    def attrs(self) -> dict[str, Any]:
        """JSON-able user attributes for the study's record."""
        out = {k: v for k, v in self.__dict__.items() if k != "parts"}
        return out | {f"part_{k}": v for k, v in self.parts.items()}


def _margin(
    curve: Sequence[tuple[float, float]], window: tuple[float, float], sign: int
) -> float | None:
    """sign = -1: -min d over the window; +1: max d over it (None if no probe is there)."""
    ds = [d for x, d in curve if window[0] <= x <= window[1]]
    if not ds:
        return None
    return -min(ds) if sign < 0 else max(ds)


def fold_of(betas: Sequence[float], margins: Sequence[float | None], rising: bool) -> float:
    """Where the margin crosses zero in beta: the first crossing from the side where the gait
    is absent (m < 0) to where it exists, scanning from the absent side (low beta for the
    metachronal, `rising`; high beta for the tripod). Without such a crossing, the gait is
    present at the scan's start (m >= 0 there: the fold lies before it) or absent to its end
    (the fold lies after it): extrapolated linearly from the two points at that end when the
    margin grows along the scan there, else (a margin that does not approach zero from that
    side) put at the far clip; always within `FOLD_CLIP`."""
    pts = [(b, m) for b, m in zip(betas, margins, strict=True) if m is not None]
    before, after = (FOLD_CLIP[0], FOLD_CLIP[1]) if rising else (FOLD_CLIP[1], FOLD_CLIP[0])
    if len(pts) < 2:
        return before
    if not rising:
        pts = pts[::-1]
    for (b0, m0), (b1, m1) in itertools.pairwise(pts):
        if m0 < 0 <= m1:
            return float(np.clip(b0 + (b1 - b0) * (-m0) / (m1 - m0), *FOLD_CLIP))
    if pts[0][1] >= 0:  # present from the start: the fold lies before it
        (b0, m0), (b1, m1) = pts[0], pts[1]
        if m1 <= m0:
            return before
        return float(np.clip(b0 - m0 * (b1 - b0) / (m1 - m0), *FOLD_CLIP))
    (b0, m0), (b1, m1) = pts[-2], pts[-1]  # absent to the end: the fold lies after it
    if m1 <= m0:
        return after
    return float(np.clip(b1 - m1 * (b1 - b0) / (m1 - m0), *FOLD_CLIP))


def read_surface(surface: DriftSurface, walking: Sequence[dict[str, Any]]) -> SurfaceScore:
    """The score of one candidate's coarse surface; `walking` are its probes' raw results (for
    speed, slip and landing share)."""
    betas = surface.betas
    m_m: list[float | None] = []
    m_t: list[float | None] = []
    extra = 0
    for b in betas:
        curve = [(float(p.d31 or 0.0), float(p.drift or 0.0)) for p in surface.curve_at(b)]
        m_m.append(_margin(curve, METACHRONAL_SIDE, -1))
        m_t.append(_margin(curve, TRIPOD_FEED, +1))
        stable = [z.d31 for z in surface.zeros_at(b) if z.stable]
        meta = [x for x in stable if METACHRONAL_WINDOW[0] <= x <= METACHRONAL_WINDOW[1]]
        trip = [x for x in stable if TRIPOD_WINDOW[0] <= x <= TRIPOD_WINDOW[1]]
        wanted = int(b >= PAPER_METACHRONAL_FOLD and bool(meta)) + int(
            b <= PAPER_TRIPOD_FOLD and bool(trip)
        )
        extra += len(stable) - wanted
    f_m = fold_of(betas, m_m, rising=True)
    f_t = fold_of(betas, m_t, rising=False)
    hi, lo = max(betas), min(betas)
    meta_hi = [z.d31 for z in surface.zeros_at(hi) if z.stable
               and METACHRONAL_WINDOW[0] <= z.d31 <= METACHRONAL_WINDOW[1]]  # fmt: skip
    trip_lo = [z.d31 for z in surface.zeros_at(lo) if z.stable
               and TRIPOD_WINDOW[0] <= z.d31 <= TRIPOD_WINDOW[1]]  # fmt: skip
    mv = min(meta_hi, key=lambda x: abs(x - METACHRONAL_TARGET), default=None)
    tv = min(trip_lo, key=lambda x: abs(x - TRIPOD_TARGET), default=None)
    usable = [p for p in surface.points if p.usable]
    unusable = 1.0 - len(usable) / max(1, len(surface.points))
    ok = [r for r in walking if r.get("error") is None]
    speed = _median([r.get("speed_ratio") for r in ok])
    slip = _median([r.get("slip_fraction") for r in ok])
    land = _median([r.get("landing_swing_share") for r in ok])
    # a measure no probe gave adds nothing here: failed probes count in `unusable`
    sanity = (
        (0.0 if speed is None else max(0.0, abs(speed - 1.0) - 0.1))
        + (0.0 if slip is None else max(0.0, slip - 0.1))
        + (0.0 if land is None else max(0.0, abs(land - 1.0) - 0.05))
        + max(0.0, unusable - UNUSABLE_SHARE_OK)
    )
    parts = {
        "metachronal_fold": abs(f_m - PAPER_METACHRONAL_FOLD),
        "tripod_fold": abs(f_t - PAPER_TRIPOD_FOLD),
        # a missing branch value costs as much as 0.5 rad off
        "metachronal_value": BRANCH_WEIGHT * (0.5 if mv is None else abs(mv - METACHRONAL_TARGET)),
        "tripod_value": BRANCH_WEIGHT * (0.5 if tv is None else abs(tv - TRIPOD_TARGET)),
        "extra_zeros": EXTRA_ZERO_WEIGHT * extra,
        "sanity": SANITY_WEIGHT * sanity,
    }
    return SurfaceScore(m_m, m_t, f_m, f_t, mv, tv, extra, speed, slip, land, unusable, parts)


def _median(xs: Sequence[Any]) -> float | None:
    v = [float(x) for x in xs if x is not None and math.isfinite(float(x))]
    return float(np.median(v)) if v else None


def evaluate_candidate(
    params: ModelParams,
    cache: ResultCache,
    backend: Backend,
    *,
    betas: Sequence[float] = OBJECTIVE_BETAS,
    config: SurfaceConfig = OBJECTIVE_CONFIG,
) -> tuple[SurfaceScore, DriftSurface]:
    """One candidate's coarse surface (every probe through the cache) and its score."""
    surface = drift_surface(betas, cache=cache, backend=backend, config=config, params=params,
                            refine=False, progress=False)  # fmt: skip
    walking = []
    for probe in grid_probes(betas, config):  # the surface's own first pass, beta outer
        v0 = 100 * nominal_speed(
            probe.beta, params.trajectory.stroke, params.trajectory.swing_duration
        )  # cm/s
        res = cache.get(run_task(probe_spec(probe, config), params)) or {}
        s = res.get("speed_cm_s")
        walking.append(res | {"speed_ratio": None if s is None else s / v0})
    return read_surface(surface, walking), surface

"""Gait measures: Delta31 statistics, gait names, speed, duty factor, footfall data.

The paper reads the gait from one number, Delta31 = phi3 - phi1 at leg-1 touchdown: pi for the
tripod, 2 pi / 3 for the metachronal gait (Sec. II B 5), with the model's branches at 2.9 and
1.9 rad (Fig. 5). A gait is a footfall pattern, though: which legs swing together and in which
order. `footfall_gait` names it from the legs' lift-off phases and the swing's length, so the
same Delta31 can be a tripod at a low duty factor and a wave at a high one; `classify_gait`
applies it to the pattern a Delta31 implies (eq. 7's antiphase sides, Delta53 = Delta31), and
a finished run's label reads its own measured footfall (`measured_footfall`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

TWO_PI = 2.0 * math.pi
TRIPOD = math.pi
METACHRONAL = TWO_PI / 3.0
# The footfall rules (`footfall_gait`; Delta31 windows would cut through the model's own
# branches at beta 0.56 and >= 0.75 and on downhill slopes).
# tripod: each tripod's three legs are in the air together for at least this share of the time
# any of them is (the "tripod coordination strength" of Wosnitza et al., J. Exp. Biol. 216,
# 480 (2013)): half, the midpoint between a lock-step tripod (1) and three legs that never all
# swing at once (0). For the ideal pattern: Delta31 within pi (1 - beta) / 3 of pi.
TRIPOD_TCS_MIN = 0.5
# metachronal: on each side the legs lift off hind -> middle -> fore (each leg leads its front
# neighbour by less than half a cycle), and no two neighbours on a side share more than this
# share of a swing in the air (more, and a side stands on one leg for most of a swing: the
# reduced model's 0.8-1.2 rad states). For the ideal pattern: Delta31 above pi (1 - beta).
NEIGHBOUR_SWING_SHARE_MAX = 0.5
# paper leg order (anatomy.LEG_NAMES: R1 L1 R2 L2 R3 L3): the two tripods and, per side, the
# neighbours (front leg, the leg behind it)
TRIPODS = ((0, 3, 4), (1, 2, 5))
NEIGHBOURS = ((0, 2), (2, 4), (1, 3), (3, 5))
# The gait a result reports for a run that has not settled by `settling` (its d31_final is
# still where it ended): neither gait is claimed for a run that is still moving.
NOT_SETTLED = "not settled"
# The gait a run walks *now* (the viewer's live label, a ramp's gait at a moment, short
# screening runs): the last WINDOW_LAST leg-1 touchdowns (about 8 gait cycles) spread less than
# WINDOW_STD (circular std, rad). Blind to the 0.2-20 mrad per cycle drift of this model's
# ghosts, so never a claim that a run has settled: that is `settling`.
WINDOW_STD = 0.15
WINDOW_LAST = 8
# THE settled rule (`settling`), used everywhere a run's end is reported (RunMeasures.d31_final
# and gait, the API's run and sweep, the fixed-point finder, the reproduction's finals): the
# least-squares drift per gait cycle over the last quarter of a run, below this (rad per leg-1
# touchdown).
# Measured (40 s runs, beta 0.62-0.70, 8 starts each): true attractors drift
# <= 0.1 mrad per cycle over 30-40 s, while a tripod start at beta 0.655 still slides off its
# ghost at 0.4-0.8 mrad per cycle after 30-40 s (and at 2.8 mrad later): the old 5 mrad rule
# called those settled. A passage slower than 0.2 mrad per cycle moves < 0.1 rad in 500
# cycles (~45 s): beyond what a run of that length can tell from a fixed point.
TAIL_DRIFT_SETTLED = 2e-4
# The tail must hold this many leg-1 touchdowns (a run of >= 4x as many, ~14-18 s at beta
# 0.62-0.70) for its drift to be resolved: with the measured 1-4 mrad scatter of a settled
# tail, 40 points resolve a slope to ~1e-5 rad per cycle, 20x below the rule.
SETTLED_MIN_TAIL = 40
# A slope walk still walks up or down the slope while the body's heading stays within this
# (deg) of the slope's line (over 60 s at +-20 deg); the default contact turns 70-110 deg
# downhill, the paper's ground stays within 1 (docs/MODEL.md, "Slopes").
HEADING_KEPT_DEG = 15.0
# What a sound run looks like, for the warnings a result carries (`run_warnings`): at the
# defaults (beta 0.58-0.75, both gaits, 5 s) the measured duty factor is 0.003-0.008 below the
# commanded beta and feet land at 1.009-1.018 of their swing (measured).
DUTY_TOLERANCE = 0.02
LANDING_BAND = (0.9, 1.1)
# stance feet leaving and pressing in again, per touchdown: up to 1.3 on today's contact and
# 2.0 on the penalty ground in the numerics grid's sound runs, 10-50 where a ground chatters
# (penalty ground 2e4 N/m at 5e-5 s; 2e-4 s at 2000 N/m)
RETOUCH_LIMIT = 5.0


def wrap(x: np.ndarray | float) -> np.ndarray:
    """Map angles to [0, 2 pi)."""
    return np.mod(np.asarray(x, dtype=float), TWO_PI)


def angle_diff(a: np.ndarray | float, b: np.ndarray | float) -> np.ndarray:
    """Signed smallest difference a - b, in (-pi, pi]."""
    d = np.mod(np.asarray(a, dtype=float) - np.asarray(b, dtype=float) + math.pi, TWO_PI)
    return d - math.pi


def circular_mean(angles: np.ndarray | list[float]) -> float:
    a = np.asarray(angles, dtype=float)
    if a.size == 0:
        raise ValueError("circular mean of no angles")
    return float(wrap(math.atan2(np.sin(a).mean(), np.cos(a).mean())))


def circular_std(angles: np.ndarray | list[float]) -> float:
    a = np.asarray(angles, dtype=float)
    r = math.hypot(np.sin(a).mean(), np.cos(a).mean())
    return math.sqrt(max(0.0, -2.0 * math.log(max(r, 1e-300))))


def _spread(starts: np.ndarray) -> float:
    """The shortest arc of the circle that holds every angle of `starts` (rad)."""
    a = np.sort(wrap(starts))
    gaps = np.diff(np.concatenate([a, a[:1] + TWO_PI]))
    return float(TWO_PI - gaps.max())


def tripod_strength(lift: np.ndarray, swing: float) -> float:
    """The weaker tripod's coordination strength: the time its three legs swing together over
    the time any of them swings (swings of length `swing` rad starting at `lift`, (6,) lift-off
    phases, any origin). 1 for a lock-step tripod, 0 when the three never all swing at once."""
    out = 1.0
    for group in TRIPODS:
        w = _spread(lift[list(group)])
        out = min(out, max(0.0, swing - w) / min(TWO_PI, swing + w))
    return out


def neighbour_swing_share(lift: np.ndarray, swing: float) -> float:
    """The most any two neighbours on a side are in the air together, as a share of a swing."""
    worst = 0.0
    for front, back in NEIGHBOURS:
        gap = abs(float(angle_diff(lift[front], lift[back])))
        both = max(0.0, swing - gap) + max(0.0, swing - (TWO_PI - gap))
        worst = max(worst, both / swing)
    return worst


def back_to_front(lift: np.ndarray) -> bool:
    """On both sides each leg lifts off before its front neighbour, by less than half a cycle:
    the wave runs hind -> middle -> fore."""
    lead = [float(angle_diff(lift[front], lift[back])) for front, back in NEIGHBOURS]
    return all(0.0 < x < math.pi for x in lead)


def footfall_gait(lift: np.ndarray, swing: float) -> str:
    """'tripod', 'metachronal' or 'other' from a footfall pattern: `lift` (6,) the legs'
    lift-off phases in one gait cycle (rad, paper leg order, any origin), `swing` the swing's
    length (rad; 2 pi (1 - beta) as commanded). Tripod: each tripod swings as one
    (TRIPOD_TCS_MIN); metachronal: a hind -> middle -> fore wave on both sides whose neighbours
    share little swing (NEIGHBOUR_SWING_SHARE_MAX); anything else is 'other'."""
    lift = np.asarray(lift, dtype=float)
    if not (np.all(np.isfinite(lift)) and 0.0 < swing < TWO_PI):
        return "other"
    if tripod_strength(lift, swing) >= TRIPOD_TCS_MIN:
        return "tripod"
    if back_to_front(lift) and neighbour_swing_share(lift, swing) <= NEIGHBOUR_SWING_SHARE_MAX:
        return "metachronal"
    return "other"


def ideal_lifts(d31: float) -> np.ndarray:
    """(6,) lift-off phases of the pattern a Delta31 implies: each middle leg ahead of its fore
    neighbour and each hind leg ahead of its middle neighbour by Delta31 (Delta53 = Delta31,
    which eq. 7's middle coupling locks), the sides half a cycle apart. A leg lifts when its
    phase reaches 2 pi, so a phase ahead by D lifts D earlier."""
    side = np.array([0.0, math.pi, 0.0, math.pi, 0.0, math.pi])
    rank = np.array([0.0, 0.0, 1.0, 1.0, 2.0, 2.0])  # fore, middle, hind
    return wrap(side - rank * d31)


def classify_gait(d31: float | None, beta: float) -> str:
    """`footfall_gait` of the pattern a settled Delta31 (rad) implies at duty factor beta."""
    if d31 is None or not math.isfinite(d31):
        return "other"
    return footfall_gait(ideal_lifts(float(d31)), TWO_PI * (1.0 - beta))


def measured_footfall(
    touchdowns: Sequence[np.ndarray], liftoffs: Sequence[np.ndarray], t0: float, t1: float
) -> tuple[np.ndarray, float] | None:
    """(lift-off phases (6,), swing length) walked in [t0, t1], rad: each leg's lift-offs
    placed in leg 1's cycles (circular mean), each swing's length over its cycle's period
    (mean over legs). None when leg 1 completes fewer than 2 cycles or a leg never lifts."""
    lo1 = np.asarray(liftoffs[0], dtype=float)
    lo1 = lo1[(lo1 >= t0) & (lo1 <= t1)]
    if lo1.size < 3:
        return None
    lift = np.zeros(6)
    swings: list[float] = []
    for leg in range(6):
        lo = np.asarray(liftoffs[leg], dtype=float)
        lo = lo[(lo >= lo1[0]) & (lo < lo1[-1])]
        if lo.size == 0:
            return None
        k = np.searchsorted(lo1, lo, side="right") - 1
        period = lo1[k + 1] - lo1[k]
        lift[leg] = circular_mean(TWO_PI * (lo - lo1[k]) / period)
        td = np.asarray(touchdowns[leg], dtype=float)
        nxt = np.searchsorted(td, lo, side="right")
        ok = nxt < td.size
        swings.extend((TWO_PI * (td[nxt[ok]] - lo[ok]) / period[ok]).tolist())
    if not swings:
        return None
    return lift, float(np.mean(swings))


def window_d31(d31: np.ndarray | Sequence[float]) -> float | None:
    """Where the last WINDOW_LAST Delta31 samples sit, if they spread less than WINDOW_STD;
    None while the run moves (or with fewer than 3 samples). The gait a run walks now, for live
    labels, a ramp's moments and short screening runs: not whether it has settled."""
    d = np.asarray(d31, dtype=float)
    if d.size < 3:
        return None
    tail = d[-WINDOW_LAST:]
    return circular_mean(tail) if circular_std(tail) <= WINDOW_STD else None


def window_gait(d31: np.ndarray | Sequence[float], beta: float) -> str:
    """`classify_gait` of `window_d31` at duty factor beta: 'other' while the run moves."""
    return classify_gait(window_d31(d31), beta)


# The live label's words besides the footfall's: a walk whose Delta31 drifts faster than the
# settled rule allows, resolved (drift beyond 2 standard errors of TAIL_DRIFT_SETTLED) over its
# last LIVE_LAST touchdowns, is "changing" whatever its footfall looks like for the moment.
CHANGING = "changing"
LIVE_LAST = 8


def live_gait(
    d31: Sequence[float],
    d31_times: Sequence[float],
    touchdowns: Sequence[Sequence[float]],
    liftoffs: Sequence[Sequence[float]],
    now_s: float,
    beta: float,
) -> str:
    """The gait walked now, as the footfall diagram shows it: CHANGING while Delta31 (leg-1
    touchdown samples `d31` at `d31_times`) drifts faster than the settled rule over the last
    LIVE_LAST samples, else `footfall_gait` of the footfall measured over the last three
    cycles (`measured_footfall`), or `window_gait` of Delta31 while too few cycles exist."""
    d = np.unwrap(np.asarray(d31, dtype=float)[-LIVE_LAST:])
    if d.size >= 6:
        slope, se = drift_fit(d)
        if abs(slope) - 2.0 * se > TAIL_DRIFT_SETTLED:
            return CHANGING
    times = np.asarray(d31_times, dtype=float)
    if times.size >= 4:
        walked = measured_footfall(
            [np.asarray(t, dtype=float) for t in touchdowns],
            [np.asarray(t, dtype=float) for t in liftoffs],
            float(times[-4]),
            now_s,
        )
        if walked is not None:
            return footfall_gait(*walked)
    return window_gait(d31, beta)


def final_d31(d31: np.ndarray | Sequence[float]) -> float | None:
    """Where a run ends: `settling`'s final (the circular mean of the last quarter); a run too
    short for a quarter of 4 touchdowns ends at the mean of its last WINDOW_LAST samples (None
    below 3). Its gait is named only if it has settled (`run_gait`)."""
    s = settling(d31)
    if s.final is not None:
        return s.final
    d = np.asarray(d31, dtype=float)
    return circular_mean(d[-WINDOW_LAST:]) if d.size >= 3 else None


def run_gait(settle: Settling, footfall: tuple[np.ndarray, float] | None) -> str:
    """The gait a finished run reports: `footfall_gait` of its last quarter's measured footfall
    if it has settled by `settling`, NOT_SETTLED otherwise (no gait is claimed for a run that
    is still moving). The one definition results report."""
    if not settle.settled:
        return NOT_SETTLED
    return "other" if footfall is None else footfall_gait(*footfall)


def mean_after(
    times_s: np.ndarray | Sequence[float], d31: np.ndarray | Sequence[float], after_s: float
) -> tuple[float | None, int]:
    """(circular mean, count) of the Delta31 samples at or after `after_s`: where a run sits
    once its transient is dropped (the bifurcation diagram's points); (None, 0) without any."""
    t = np.asarray(times_s, dtype=float)
    d = np.asarray(d31, dtype=float)[t >= after_s]
    return (circular_mean(d) if d.size else None), int(d.size)


@dataclass(frozen=True)
class Settling:
    """Where a run ends and whether it has stopped moving there (`settling`)."""

    final: float | None  # circular mean of the last quarter, rad (None: too few touchdowns)
    drift: float | None  # least-squares drift per gait cycle over that quarter, rad
    drift_se: float | None  # its standard error, rad per cycle
    tail: int  # touchdowns in the last quarter
    settled: bool
    why: str  # "" when settled, else the reason in words


def drift_fit(tail: np.ndarray) -> tuple[float, float]:
    """(drift per sample, its standard error): the least-squares line through an unwrapped
    Delta31 series, one sample per gait cycle (the settled rule's and the live label's fit)."""
    n = tail.size
    k = np.arange(n, dtype=float)
    slope, icpt = np.polyfit(k, tail, 1)
    resid = tail - (slope * k + icpt)
    se = float(np.sqrt(resid @ resid / max(1, n - 2) / ((k - k.mean()) @ (k - k.mean()))))
    return float(slope), se


def settling(d31: np.ndarray | Sequence[float]) -> Settling:
    """THE settled test of a run's Delta31 series (one sample per gait cycle): the last
    quarter holds >= SETTLED_MIN_TAIL touchdowns and its drift per cycle, resolved to better
    than half the rule (2 standard errors), is below TAIL_DRIFT_SETTLED. A run too short to
    resolve its drift is "not settled", never guessed."""
    d = np.asarray(d31, dtype=float)
    n = d.size // 4
    if n < 4:
        return Settling(None, None, None, n, False, f"{d.size} touchdowns: too few to judge")
    tail = np.unwrap(d[-n:])
    drift, se = drift_fit(tail)
    final = circular_mean(tail)
    if n < SETTLED_MIN_TAIL:
        why = f"last quarter holds {n} touchdowns (< {SETTLED_MIN_TAIL}): run longer"
    elif abs(drift) + 2 * se > TAIL_DRIFT_SETTLED:
        why = (
            f"still drifting {drift * 1e3:+.2f} mrad per cycle (rule {TAIL_DRIFT_SETTLED * 1e3:g})"
        )
    else:
        why = ""
    return Settling(final, drift, se, n, not why, why)


def phase_jumps(
    times: Sequence[np.ndarray], phases: Sequence[np.ndarray], phi_aep: float, after_s: float
) -> np.ndarray:
    """(6,) mean phase jump e_i = phi_AEP - phi_touchdown each leg's touchdowns after `after_s`
    cause (eq. 4; e > 0 when the leg lands early); NaN for a leg with none."""
    out = np.full(6, np.nan)
    for leg, (t, ph) in enumerate(zip(times, phases, strict=True)):
        sel = np.asarray(ph)[np.asarray(t) > after_s]
        if sel.size:
            out[leg] = float(np.mean(angle_diff(phi_aep, sel)))
    return out


def drift_per_cycle(jumps: np.ndarray) -> np.ndarray:
    """Delta31 drift per gait cycle from the legs' phase jumps (..., 6): 1/4 [(e5 + e6) -
    (e1 + e2)]. With K13 = K53 = 0 the middle oscillators lock to the mean of fore and hind,
    so only the fore and hind resets last (shared/notes/gait-mechanism.md)."""
    j = np.asarray(jumps, dtype=float)
    return 0.25 * ((j[..., 4] + j[..., 5]) - (j[..., 0] + j[..., 1]))


def duty_factor(stance: np.ndarray, fraction: float = 0.5) -> float | None:
    """Mean stance fraction over the last `fraction` of the record, all legs."""
    if stance.shape[0] < 4:
        return None
    tail = stance[int(stance.shape[0] * (1.0 - fraction)) :]
    return float(tail.mean())


def yaw_of(wxyz: np.ndarray | Sequence[float]) -> np.ndarray:
    """Heading (rad, from world +x towards +y) of the body's x axis (the model's forward axis)
    for unit quaternions wxyz, (4,) or (T, 4). The floor is the world's z = 0 plane at every
    slope (the model tilts gravity, not the floor), so the heading lives in the xy plane."""
    q = np.asarray(wxyz, dtype=float)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.arctan2(2.0 * (x * y + w * z), 1.0 - 2.0 * (y * y + z * z))


def heading_speed(
    times: np.ndarray, pos: np.ndarray, quat: np.ndarray
) -> tuple[float | None, float | None]:
    """(speed m/s, heading rad) over a stretch of record: the body's displacement from its
    first to its last sample projected on its mean heading (a circular mean), per second.
    Negative is backwards. Along world x instead, a body that has turned reads nonsense (after
    a slope the viewer said -0.26 cm/s for minutes while the insect walked forwards)."""
    if times.shape[0] < 2 or times[-1] - times[0] <= 0:
        return None, None
    yaw = yaw_of(quat)
    heading = math.atan2(float(np.sin(yaw).mean()), float(np.cos(yaw).mean()))
    dx, dy = pos[-1, 0] - pos[0, 0], pos[-1, 1] - pos[0, 1]
    along = dx * math.cos(heading) + dy * math.sin(heading)
    return float(along / (times[-1] - times[0])), heading


def forward_speed(
    times: np.ndarray, pos: np.ndarray, quat: np.ndarray, fraction: float = 0.5
) -> float | None:
    """A run's speed (m/s): `heading_speed` over the last `fraction` of its record."""
    if times.shape[0] < 4:
        return None
    i0 = int(times.shape[0] * (1.0 - fraction))
    return heading_speed(times[i0:], pos[i0:], quat[i0:])[0]


def landing_share(
    times: tuple[np.ndarray, ...], phases: tuple[np.ndarray, ...], phi_aep: float, after_s: float
) -> float | None:
    """Median share of the swing done when a foot lands, over every leg's touchdowns after
    `after_s`: 1 - (phi_AEP - phi_touchdown) / phi_AEP, so 1 is at the AEP and 0.5 is where
    the scuff window closes (at the default `scuff_fraction`). Phase resets feed on how early
    feet land; an attractor reached with feet landing in mid-swing is shaped by the swing
    curve and the scuff rule, not by walking (docs/studies/journal.md, fourth study)."""
    ph = np.concatenate([p[t > after_s] for t, p in zip(times, phases, strict=True)])
    if ph.size == 0:
        return None
    return float(np.median(1.0 - angle_diff(phi_aep, ph) / phi_aep))


def run_warnings(
    *,
    beta: float,
    duty_factor: float | None,
    landing: float | None,
    integrator: str,
    dt_s: float,
    converged_dt_s: float,
    retouches: float | None = None,
) -> list[str]:
    """What a finished run's numbers say about themselves, in words for the person reading
    them: a duty factor off the commanded beta, feet landing far from the AEP, a step coarser
    than the converged default. Empty for a sound run."""
    out = []
    coarse = dt_s > converged_dt_s * (1 + 1e-9)
    if duty_factor is not None and abs(duty_factor - beta) > DUTY_TOLERANCE:
        why = " (a coarse step: see docs/NUMERICS.md)" if coarse else ""
        out.append(
            f"measured duty factor {duty_factor:.3f} differs from the commanded beta {beta:.3f} "
            f"by more than {DUTY_TOLERANCE:g}: the legs do not follow their oscillators{why}"
        )
    if landing is not None and not LANDING_BAND[0] <= landing <= LANDING_BAND[1]:
        when = (
            "late: the oscillator was already in stance and the foot was still lowering"
            if landing > 1
            else "early: mid-swing, before the AEP"
        )
        out.append(
            f"landing_swing_share {landing:.3f}: feet touch down {when} (1 = at the AEP; sound "
            f"runs land within {LANDING_BAND[0]:g}-{LANDING_BAND[1]:g})"
        )
    if retouches is not None and retouches > RETOUCH_LIMIT:
        out.append(
            f"stance feet leave and press into the ground {retouches:.1f} times per stance "
            f"(sound runs: below {RETOUCH_LIMIT:g}): the contact chatters, the step is too "
            "coarse for the ground's stiffness"
        )
    if coarse:
        out.append(
            f"{integrator} at dt_s {dt_s:g} s is coarser than the converged default "
            f"({converged_dt_s:g} s): the numbers are not converged (docs/NUMERICS.md)"
        )
    return out


def stance_intervals(
    touchdowns: Sequence[Sequence[float]],
    liftoffs: Sequence[Sequence[float]],
    t0: float,
    t1: float,
) -> list[list[tuple[float, float]]]:
    """Per leg, the stance intervals (touchdown, next lift-off) overlapping [t0, t1], clipped."""
    out: list[list[tuple[float, float]]] = []
    for td, lo in zip(touchdowns, liftoffs, strict=True):
        lo_arr = np.asarray(lo, dtype=float)
        leg: list[tuple[float, float]] = []
        for a in td:
            later = lo_arr[lo_arr > a]
            b = float(later[0]) if later.size else t1
            if b >= t0 and a <= t1:
                leg.append((max(a, t0), min(b, t1)))
        out.append(leg)
    return out

"""A quasi-static support model of the phase resets: which gait would sag alone select?

The simplest mechanism by which body mechanics could pick a gait through eq. 4: a rigid body on
equally stiff, instantly settling legs sags most where the support is weakest, and a swing foot
whose hip sags lands early (a positive phase jump e). With Delta31 held fixed and the middle
oscillators locked to the mean of fore and hind (eqs. 5-7), the drift per cycle is
1/4 [(e5 + e6) - (e1 + e2)], as in `calibration.open_loop_drift`, but here each e is the
quasi-static deflection at the landing hip under the legs in stance just before the landing.

This is a diagnostic, not the model: it has no dynamics, no swing-curve shape and no ground.
It answers where a sag-driven branch would sit (a stable zero crossing of the drift) and how it
moves with beta, so that the full simulation's return maps can be read against it
(docs/REPRODUCTION.md). Units: lengths in any one unit, deflections relative (weight / k = 1).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sim_core.contract import TWO_PI
from sim_core.research import drift_per_cycle


@dataclass(frozen=True)
class SupportGeometry:
    """Foot positions in stance relative to the centre of mass (paper leg order R1 L1 ... L3)."""

    x_fore: float = 12.0
    x_mid: float = 0.0
    x_hind: float = -12.0
    y: float = 11.0
    com_x: float = 0.0

    def feet(self) -> tuple[np.ndarray, np.ndarray]:
        x = np.array([self.x_fore] * 2 + [self.x_mid] * 2 + [self.x_hind] * 2, dtype=float)
        y = np.array([-self.y, self.y] * 3, dtype=float)
        return x, y


def leg_offsets(d31: float) -> np.ndarray:
    """Phase lead of each leg over leg 1 in cycles, with eqs. 5-7 satisfied exactly."""
    a = d31 / (TWO_PI)
    return np.array([0.0, 0.5, a, a + 0.5, 2 * a, 2 * a + 0.5]) % 1.0


def landing_sag(beta: float, d31: float, geo: SupportGeometry | None = None) -> np.ndarray:
    """Hip deflection of each leg at its own landing (NaN where the support is degenerate).

    The body is a rigid plate on unit springs at the stance feet; heave, pitch and roll solve
    force and moment balance for a unit weight at the centre of mass.
    """
    g = geo or SupportGeometry()
    x, y = g.feet()
    off = leg_offsets(d31)
    aep = 1.0 - beta  # landing at phase fraction 1 - beta; stance until 1
    sag = np.full(6, np.nan)
    for j in range(6):
        t = aep - off[j] - 1e-9  # just before leg j lands
        ph = (t + off) % 1.0
        support = [i for i in range(6) if i != j and ph[i] >= aep]
        a = np.stack([np.ones(len(support)), x[support], y[support]], axis=1)
        k = a.T @ a
        if np.linalg.matrix_rank(k) < 3:
            continue
        heave_pitch_roll = np.linalg.solve(k, np.array([1.0, g.com_x, 0.0]))
        sag[j] = float(np.array([1.0, x[j], y[j]]) @ heave_pitch_roll)
    return sag


def quasi_static_drift(
    beta: float, d31: Sequence[float] | np.ndarray, geo: SupportGeometry | None = None
) -> np.ndarray:
    """Delta31 drift per cycle, 1/4 [(e5 + e6) - (e1 + e2)], with e proportional to the sag."""
    out = []
    for d in np.asarray(d31, dtype=float):
        e = landing_sag(beta, float(d), geo)
        out.append(float(drift_per_cycle(e)))
    return np.array(out)


def stable_points(beta: float, grid: np.ndarray, geo: SupportGeometry | None = None) -> list[float]:
    """Where the drift turns from positive to negative along the grid (midpoints)."""
    d = quasi_static_drift(beta, grid, geo)
    pts = []
    for k in range(len(grid) - 1):
        if np.isfinite(d[k]) and np.isfinite(d[k + 1]) and d[k] > 0 >= d[k + 1]:
            pts.append(0.5 * float(grid[k] + grid[k + 1]))
    return pts


def _hull_margin(pts: np.ndarray, c: np.ndarray) -> float:
    """Signed distance from c to the boundary of the convex hull of pts (> 0 inside)."""
    order = sorted(map(tuple, pts))

    def cross(o: tuple[float, ...], a: tuple[float, ...], b: tuple[float, ...]) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple[float, ...]] = []
    upper: list[tuple[float, ...]] = []
    for p in order:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(order):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    hull = np.array(lower[:-1] + upper[:-1])  # counter-clockwise
    edges = np.roll(hull, -1, axis=0) - hull
    rel = c - hull
    dist = (edges[:, 0] * rel[:, 1] - edges[:, 1] * rel[:, 0]) / np.hypot(edges[:, 0], edges[:, 1])
    return float(dist.min())


def static_margin(
    beta: float,
    d31: float,
    *,
    geo: SupportGeometry | None = None,
    stroke: float = 2.0,
    samples: int = 720,
) -> tuple[float, int]:
    """(smallest static stability margin over a cycle, fewest legs in stance) for a gait.

    The margin is how far the centre of mass lies inside the polygon of the stance feet
    (negative: outside, the body must tip), with every foot on its stance line moving from
    +stroke/2 to -stroke/2 about its centre over the stance. Three-leg supports other than the
    two tripods (two legs of one side and the diagonal opposite) leave the centre of mass on or
    near a diagonal edge; `docs/studies/journal.md` (fifth study) reads the full model against this.
    """
    g = geo or SupportGeometry()
    x, y = g.feet()
    off = leg_offsets(d31)
    aep = 1.0 - beta
    worst, fewest = math.inf, 6
    for t in np.linspace(0.0, 1.0, samples, endpoint=False):
        ph = (t + off) % 1.0
        on = ph >= aep
        fewest = min(fewest, int(on.sum()))
        if on.sum() < 3:
            return -math.inf, fewest
        frac = (ph[on] - aep) / (1.0 - aep)
        feet = np.stack([x[on] + stroke * (0.5 - frac), y[on]], axis=1)
        worst = min(worst, _hull_margin(feet, np.array([g.com_x, 0.0])))
    return worst, fewest

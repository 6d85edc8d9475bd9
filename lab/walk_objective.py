"""The sixth campaign's objective (issue 52, point 3): free walks from both of the paper's
branch values, read as "holds" or "leaves", at betas on both sides of both folds.

Why walks and not the pinned surface: in the soft-leg regime the surface misses states the
walks hold and shows zeros the walks pass through (docs/studies/soft_legs.md), and in the stiff
one campaign 5's best surfaces had loops that free walks did not (issue 52). A walk from the
paper's metachronal value (1.9) and one from its tripod value (2.9) at each of `WALK_BETAS`
answer the paper's question directly: which gait survives where. The paper's answer: the
metachronal walk holds from 0.645 up, the tripod walk holds up to 0.67, both hold in between.

A walk *holds* when the mean Delta31 of its last quarter lies in the branch's window and its
drift per gait cycle there (the core's least-squares fit, `settling`) is below `HOLD_DRIFT`:
a walk sliding through a ghost leaves, however slowly it has moved so far. The folds are read
from the holds along beta (the best monotone split, its mismatches counted), so this
objective resolves them to the betas' spacing; candidates that match the paper on every walk
are refined by walks at betas between (`refine_betas`).

The paper's values (Table I masses and lengths, D, T_sw, K) are never searched.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lab.surface_search import (
    METACHRONAL_TARGET,
    PAPER_METACHRONAL_FOLD,
    PAPER_TRIPOD_FOLD,
    SANITY_WEIGHT,
    TRIPOD_TARGET,
)
from sim_core import Backend, ModelParams, ResultCache, RunSpec, nominal_speed, run_task, run_tasks
from sim_core.contract import settling
from sim_core.research import angle_diff

# two betas below the metachronal fold (0.645), one between the folds (both gaits), two above
# the tripod's (0.67); 0.62 and 0.70 are Fig. 5's
WALK_BETAS = (0.62, 0.635, 0.655, 0.685, 0.70)
# the paper's values, the tripod's from 3.0 as the atlas's walks start it (`PAPER_STARTS`): at
# 0.62 the defaults' tripod basin ends at 2.88-2.91, so 2.9 would test the saddle, not the gait
STARTS = {"metachronal": METACHRONAL_TARGET, "tripod": TRIPOD_TARGET + 0.1}
# a branch's window: a walk ending here is on it (the metachronal one as campaign 5's; the
# tripod's up to pi + 0.1: the soft legs' upper state at pi + 0.2 is not the paper's tripod)
WINDOWS = {"metachronal": (1.55, 2.35), "tripod": (2.6, math.pi + 0.1)}
WALK_S = 16.0  # s per walk: its last quarter (4 s) holds >= 40 gait cycles at every beta
HOLD_DRIFT = 1e-3  # rad per cycle: above it a walk in its window is leaving (a ghost)
# score weights, in beta (as campaign 5's): a walk against the best monotone split costs as
# much as a fold 0.01 off; a branch value 0.1 rad off as much as a fold 0.01 off
MISMATCH_WEIGHT = 0.01
VALUE_WEIGHT = 0.1
FOLD_STEP = 0.015  # a fold beyond the betas' ends is read this far outside them
FAILED_SCORE = 2.0


OTHER = {"metachronal": "tripod", "tripod": "metachronal"}


def lives(side: str, beta: float) -> bool:
    """The paper's answer: does the `side` gait exist at `beta` (Fig. 8)?"""
    if side == "metachronal":
        return beta >= PAPER_METACHRONAL_FOLD
    return beta <= PAPER_TRIPOD_FOLD


@dataclass(frozen=True)
class Walk:
    """One walk's reading."""

    side: str
    beta: float
    final: float | None  # mean Delta31 of the last quarter (rad)
    drift: float | None  # rad per gait cycle over the last quarter
    holds: bool
    failed: bool
    speed_ratio: float | None
    slip: float | None
    landing_share: float | None

    def as_dict(self) -> dict[str, Any]:
        return self.__dict__.copy()


def read_walk(side: str, beta: float, result: dict[str, Any], nominal_cm_s: float) -> Walk:
    """A cached run's result read as holding its branch or leaving it."""
    if result.get("error") is not None or result.get("failure") is not None:
        return Walk(side, beta, None, None, False, True, None, None, None)
    st = settling(result["d31"])
    final = None if st.final is None else float(st.final) % (2 * math.pi)
    lo, hi = WINDOWS[side]
    holds = (
        final is not None
        and st.drift is not None
        and lo <= final <= hi
        and abs(st.drift) < HOLD_DRIFT
    )
    speed = result.get("speed_cm_s")
    return Walk(side, beta, final, st.drift, bool(holds), False,
                None if speed is None else speed / nominal_cm_s,
                result.get("slip_fraction"), result.get("landing_swing_share"))  # fmt: skip


def fold_from_holds(
    betas: Sequence[float], holds: Sequence[bool], rising: bool
) -> tuple[float, int]:
    """(fold, mismatches): the split of `betas` into absent | present (present above the split
    when `rising`, below it otherwise) that disagrees with the fewest `holds`; the fold is the
    midpoint of the split's two betas, or FOLD_STEP outside the ends when the gait is present
    (or absent) everywhere. Ties go to the split nearest the middle of the betas."""
    b = list(betas)
    h = list(holds)
    if not rising:  # scan from the absent side: the high betas for the tripod
        b, h = b[::-1], h[::-1]
    n = len(b)
    best: tuple[int, float, float] | None = None
    for k in range(n + 1):  # the first k absent, the rest present
        miss = sum(h[:k]) + sum(not x for x in h[k:])
        if k == 0:
            fold = b[0] - (FOLD_STEP if rising else -FOLD_STEP)
        elif k == n:
            fold = b[-1] + (FOLD_STEP if rising else -FOLD_STEP)
        else:
            fold = 0.5 * (b[k - 1] + b[k])
        key = (miss, abs(k - n / 2), fold)
        if best is None or key[:2] < best[:2]:
            best = key
    assert best is not None
    return best[2], best[0]


def in_window(final: float | None, side: str) -> bool:
    lo, hi = WINDOWS[side]
    return final is not None and lo <= final <= hi


def settled_elsewhere(w: Walk) -> bool:
    """The walk left its branch where the paper has only the other gait, and settled
    (|drift| below `HOLD_DRIFT`) outside the other gait's window: a third state, e.g. an upper
    state sliding past pi + 0.1 with beta. A walk still moving is on its way (a slow leaver
    through a ghost) and is not counted: 16 s cannot say where it ends."""
    return (
        not w.failed and not w.holds and w.drift is not None and abs(w.drift) < HOLD_DRIFT
        and not lives(w.side, w.beta) and not in_window(w.final, OTHER[w.side])
    )  # fmt: skip


def against_paper(w: Walk) -> bool:
    """Does the walk disagree with the paper's answer? Where the paper has its gait, the walk
    must hold it; where the paper has only the other gait, it must leave, and not for a third
    state (`settled_elsewhere`)."""
    if lives(w.side, w.beta):
        return not w.holds
    return w.holds or w.failed or settled_elsewhere(w)


def third_states(walks: Sequence[Walk]) -> int:
    """Walks settled in a third state where the paper has only the other gait."""
    return sum(map(settled_elsewhere, walks))


@dataclass
class WalkScore:
    """One candidate's walks read against the paper, and its score (lower is better)."""

    walks: list[Walk]
    metachronal_fold: float
    tripod_fold: float
    against_paper: int  # walks whose holding disagrees with the paper's answer
    metachronal_value: float | None  # the metachronal walk's final at the highest beta
    tripod_value: float | None  # the tripod walk's final at the lowest beta
    speed_ratio: float | None
    slip: float | None
    landing_share: float | None
    parts: dict[str, float] = field(default_factory=dict)

    @property
    def score(self) -> float:
        return float(sum(self.parts.values()))

    def attrs(self) -> dict[str, Any]:
        """JSON-able attributes for the study's record."""
        out = {k: v for k, v in self.__dict__.items() if k not in ("parts", "walks")}
        out["walks"] = [[w.side[0], w.beta, w.final, w.drift, w.holds] for w in self.walks]
        return out | {f"part_{k}": v for k, v in self.parts.items()}


def _median(xs: Sequence[float | None]) -> float | None:
    v = [float(x) for x in xs if x is not None and math.isfinite(float(x))]
    return float(np.median(v)) if v else None


def score_walks(walks: Sequence[Walk]) -> WalkScore:
    """The folds, branch values and walking sanity of a candidate's walks."""
    by = {(w.side, w.beta): w for w in walks}
    betas = sorted({w.beta for w in walks})
    meta = [by[("metachronal", b)].holds for b in betas]
    trip = [by[("tripod", b)].holds for b in betas]
    f_m, miss_m = fold_from_holds(betas, meta, rising=True)
    f_t, miss_t = fold_from_holds(betas, trip, rising=False)
    against = sum(against_paper(w) for w in walks)
    mv = by[("metachronal", betas[-1])]
    tv = by[("tripod", betas[0])]
    ok = [w for w in walks if not w.failed]
    speed = _median([w.speed_ratio for w in ok])
    slip = _median([w.slip for w in ok])
    land = _median([w.landing_share for w in ok])
    failed = 1.0 - len(ok) / max(1, len(walks))
    sanity = (
        (0.0 if speed is None else max(0.0, abs(speed - 1.0) - 0.1))
        + (0.0 if slip is None else max(0.0, slip - 0.1))
        + (0.0 if land is None else max(0.0, abs(land - 1.0) - 0.1))
        + failed
    )

    def value_error(w: Walk, target: float) -> float:  # a lost branch costs 0.5 rad
        if not w.holds or w.final is None:
            return 0.5
        return abs(float(angle_diff(w.final, target)))

    parts = {
        "metachronal_fold": abs(f_m - PAPER_METACHRONAL_FOLD),
        "tripod_fold": abs(f_t - PAPER_TRIPOD_FOLD),
        "mismatches": MISMATCH_WEIGHT * (miss_m + miss_t),
        "third_states": MISMATCH_WEIGHT * third_states(walks),
        "metachronal_value": VALUE_WEIGHT * value_error(mv, METACHRONAL_TARGET),
        "tripod_value": VALUE_WEIGHT * value_error(tv, TRIPOD_TARGET),
        "sanity": SANITY_WEIGHT * sanity,
    }
    return WalkScore(list(walks), f_m, f_t, against,
                     mv.final if mv.holds else None, tv.final if tv.holds else None,
                     speed, slip, land, parts)  # fmt: skip


def walk_specs(
    betas: Sequence[float] = WALK_BETAS, *, duration_s: float = WALK_S, dt_s: float | None = None
) -> list[tuple[str, RunSpec]]:
    """(side, spec) of every walk: both starts at each beta."""
    return [(side, RunSpec(beta=b, d31_init=x0, duration_s=duration_s, dt_s=dt_s))
            for b in betas for side, x0 in STARTS.items()]  # fmt: skip


def evaluate_walks(
    params: ModelParams,
    cache: ResultCache,
    backend: Backend,
    *,
    betas: Sequence[float] = WALK_BETAS,
    duration_s: float = WALK_S,
    dt_s: float | None = None,
) -> WalkScore:
    """One candidate's walks (every run through the cache) and its score."""
    specs = walk_specs(betas, duration_s=duration_s, dt_s=dt_s)
    tasks = [run_task(s, params) for _, s in specs]
    results, _ = run_tasks(tasks, cache, backend, chunk_size=1, progress=False)
    tr = params.trajectory
    walks = [
        read_walk(
            side, s.beta, results[t.key], 100 * nominal_speed(s.beta, tr.stroke, tr.swing_duration)
        )
        for (side, s), t in zip(specs, tasks, strict=True)
    ]
    return score_walks(walks)


def refine_betas(score: WalkScore, step: float = 0.005) -> list[float]:
    """Betas between the coarse split's two betas around each fold, `step` apart (for the
    candidates that match the paper's answer on every walk)."""
    out: set[float] = set()
    for f in (score.metachronal_fold, score.tripod_fold):
        lo, hi = f - 0.01, f + 0.01
        out |= {round(x, 4) for x in np.arange(lo, hi + 1e-9, step)}
    return sorted(out)

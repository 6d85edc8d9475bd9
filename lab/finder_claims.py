"""The finder's reading put through the rest of the four checks a claim needs (the
developers' guide, "How to do science"): besides **settled** (the finder's own rule), does
**dt/2** give the same attractors, do the feet land near the AEP there (**landing share**),
and does the structure survive **+-10%** of each calibrated parameter (and how far does the
fold move)?

- `numerics`: every stable point the finder reports at the given betas is re-run from the
  point itself for `CHECK_S` at the default step and at half of it; both must settle within
  `SAME_TOL` of each other (`SAME_TOL_FOLD` within `FOLD_MARGIN` of a fold),
  and the default run's landing share must lie in `LANDING_OK`.
- `robustness`: with each of `CALIBRATED` at 0.9x and 1.1x, a tripod start (`TRIPOD_START`) at
  each of `FOLD_BETAS` tells where the tripod still lives (its fold bracket), and a metachronal
  start (`METACHRONAL_START`) at the two ends of Fig. 8's grid tells whether that side still
  lives there.

Both run through `simulate_batch` (threads on this machine) rather than the task cache: the
landing share is a `RunResult` field that the cached task record does not keep. The list of
calibrated parameters and the +-10% variants are the core's (`sim_core.research.CALIBRATED`,
`scaled_values`: `insect-gait surface-check` and the readings screen use them too); this study
is `python -m lab finder-claims`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from sim_core import ModelParams, RunResult, RunSpec, simulate_batch
from sim_core.contract import FinderOutput, classify_gait, settling
from sim_core.research import CALIBRATED, SCALES, angle_diff, scaled_values

CHECK_S = 40.0  # the finder's run length (FinderConfig.duration_s)
SAME_TOL = 0.05  # rad: "each within 0.05 rad" ...
SAME_TOL_FOLD = 0.1  # ... "0.1 within 0.01 of a fold"
FOLD_MARGIN = 0.01
LANDING_OK = (0.9, 1.1)  # sane walking: feet land near the AEP
# The tripod's fold on the default lies between 0.645 and 0.65: these bracket it at 0.01 and
# show a move of up to ~0.02 either way.
FOLD_BETAS = (0.625, 0.635, 0.645, 0.655, 0.665)
TRIPOD_START = 2.97  # just above the tripod (2.94-2.96), inside its basin where it lives
METACHRONAL_START = 1.9  # the paper's metachronal gait; our family 1.69-2.27 reaches from here
METACHRONAL_BETAS = (0.62, 0.70)


@dataclass
class PointCheck:
    beta: float
    d31: float  # the finder's stable point
    gait: str
    end: float | None  # settled final at the default step (None: not settled)
    end_half: float | None  # ... at dt/2
    landing: float | None  # landing share at the default step
    tol: float

    @property
    def same(self) -> bool:
        return (
            self.end is not None
            and self.end_half is not None
            and abs(float(angle_diff(self.end, self.end_half))) <= self.tol
            and abs(float(angle_diff(self.end, self.d31))) <= self.tol
        )

    @property
    def lands_ok(self) -> bool:
        return self.landing is not None and LANDING_OK[0] <= self.landing <= LANDING_OK[1]


def _final(r: RunResult) -> float | None:
    if r.error is not None:
        return None
    s = settling(r.events.d31)
    return s.final if s.settled else None


def numerics(
    found: FinderOutput,
    betas: Sequence[float],
    folds: Sequence[float] = (),
    params: ModelParams | None = None,
    *,
    duration_s: float = CHECK_S,
    nthread: int = 0,
    progress: Callable[[float], None] | None = None,
) -> list[PointCheck]:
    """dt/2 and landing share of every stable point the finder reports at `betas`."""
    p = params or ModelParams()
    cells = [c for c in found.cells if any(abs(c.beta - b) < 1e-9 for b in betas)]
    points = [(c.beta, a) for c in cells for a in c.stable()]
    specs = [RunSpec(beta=b, d31_init=a.d31, duration_s=duration_s) for b, a in points]
    halves = [s.model_copy(update={"dt_s": p.numerics.dt / 2}) for s in specs]
    done = simulate_batch([*specs, *halves], p, nthread=nthread, progress=progress)
    out = []
    for k, (b, a) in enumerate(points):
        r, h = done[k], done[len(specs) + k]
        near_fold = any(abs(b - f) <= FOLD_MARGIN for f in folds)
        out.append(PointCheck(b, a.d31, a.gait, _final(r), _final(h),
                              r.measures.landing_swing_share,
                              SAME_TOL_FOLD if near_fold else SAME_TOL))  # fmt: skip
    return out


@dataclass
class Variant:
    name: str  # "default" or "<param> x0.9"
    tripod: list[tuple[float, float | None]]  # (beta, settled final from TRIPOD_START)
    metachronal: list[tuple[float, float | None]]  # (beta, ... from METACHRONAL_START)

    def tripod_lives(self) -> list[bool]:
        return [e is not None and classify_gait(e, b) == "tripod" for b, e in self.tripod]

    def fold(self) -> str:
        """The tripod's fold bracket along FOLD_BETAS, as text."""
        lives = self.tripod_lives()
        betas = [b for b, _ in self.tripod]
        if all(lives):
            return f"above {betas[-1]:g}"
        if not any(lives):
            return f"below {betas[0]:g}"
        last = max(k for k, ok in enumerate(lives) if ok)
        gaps = "" if all(lives[: last + 1]) and not any(lives[last + 1 :]) else " (gaps)"
        return f"{betas[last]:g}-{betas[last + 1]:g}{gaps}"


def robustness(
    params: ModelParams | None = None,
    names: Sequence[str] = CALIBRATED,
    scales: Sequence[float] = SCALES,
    *,
    duration_s: float = CHECK_S,
    nthread: int = 0,
    progress: Callable[[float], None] | None = None,
) -> list[Variant]:
    """The tripod's fold bracket and the metachronal side's ends under +-10% of each
    calibrated parameter (and on the default, first)."""
    base = params or ModelParams()
    scaled = scaled_values(base, names, scales)
    variants = [("default", base)] + [(name, base.replace(**u)) for name, u in scaled]
    runs = [(b, TRIPOD_START) for b in FOLD_BETAS] + [(b, METACHRONAL_START)
                                                       for b in METACHRONAL_BETAS]  # fmt: skip
    out: list[Variant] = []
    total = len(variants)
    for i, (name, p) in enumerate(variants):
        specs = [RunSpec(beta=b, d31_init=x, duration_s=duration_s) for b, x in runs]

        def step(f: float, i: int = i) -> None:
            if progress is not None:
                progress((i + f) / total)

        done = simulate_batch(specs, p, nthread=nthread, progress=step)
        ends = [(b, _final(r)) for (b, _), r in zip(runs, done, strict=True)]
        out.append(Variant(name, ends[: len(FOLD_BETAS)], ends[len(FOLD_BETAS) :]))
    return out


def numerics_report(checks: Sequence[PointCheck]) -> list[str]:
    """Markdown rows: one per stable point."""

    def f(x: float | None) -> str:
        return "not settled" if x is None else f"{x:.3f}"

    rows = ["| β | stable point | gait | 40 s at dt | at dt/2 | same (tol) | landing share |",
            "|---|---|---|---|---|---|---|"]  # fmt: skip
    for c in checks:
        land = "?" if c.landing is None else f"{c.landing:.2f}" + ("" if c.lands_ok else " **no**")
        rows.append(f"| {c.beta:g} | {c.d31:.3f} | {c.gait} | {f(c.end)} | {f(c.end_half)} | "
                    f"{'yes' if c.same else '**no**'} ({c.tol:g}) | {land} |")  # fmt: skip
    return rows


def robustness_report(variants: Sequence[Variant]) -> list[str]:
    """Markdown rows: one per parameter variant."""

    def f(x: float | None) -> str:
        return "–" if x is None else f"{x:.2f}"

    head = " | ".join(f"{b:g}" for b in FOLD_BETAS)
    meta = " | ".join(f"{b:g}" for b in METACHRONAL_BETAS)
    rows = [f"| variant | tripod start {TRIPOD_START} at β {head} | tripod fold | "
            f"start {METACHRONAL_START} at β {meta} |",
            "|---|" + "---|" * (len(FOLD_BETAS) + 1 + len(METACHRONAL_BETAS))]  # fmt: skip
    for v in variants:
        t = " | ".join(f(e) for _, e in v.tripod)
        m = " | ".join(f(e) for _, e in v.metachronal)
        rows.append(f"| {v.name} | {t} | {v.fold()} | {m} |")
    return rows

"""Issue 31, step 1: the two-timing-lines hypothesis tested before any search.

The hypothesis (shared/notes/gait-mechanism.md, "Two timing lines"): with Delta31 = Delta53 = D
and the sides in antiphase, two touchdown/lift-off coincidences are lines in (beta, D):

- L_DW: D = 2 pi (1 - beta): a posterior leg lands as its anterior neighbour lifts off;
- L_FH: D = pi beta: a fore leg lands as its ipsilateral hind leg lifts off.

A hind leg landing early (the body tips onto it when its middle neighbour lifts off: D below
L_DW) pushes Delta31 up; a fore leg landing early (when its hind neighbour lifts off in the
fore's late swing: D above L_FH) pulls it down. The paper's metachronal branch lies on the lower
line and dies soon after they part (beta < 2/3); ours lives on to 0.59. Three cheap tests:

1. `open_loop_legs`: with resets off and D held, each leg pair's mean phase jump at touchdown
   against D (averaged over `PHASES` starts of leg 1, whose spread is reported): where does the
   hind's early-landing ramp end (`edge`), and is there a fore bump at L_FH?
2. `chain_lags`: on closed-loop runs, the time from a middle leg's lift-off to its ipsilateral
   hind leg's next touchdown (the lag tau the hypothesis says lowers the branch by omega tau).
3. `reduced_branches`: the reduced support model (equal legs, r = 1) with leg damping setting
   its lag c/k: does its metachronal state follow min(L_DW - omega tau, L_FH) and end below 2/3?
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from lab.reduced_model import ReducedParams, run_reduced
from sim_core import ModelParams, RunSpec, simulate_batch
from sim_core.contract import TWO_PI, settling
from sim_core.research import phase_jumps, phi_aep

# Leg 1's start phase over these: an open-loop probe's jumps depend a little on where the cycle
# starts (the legs of a pair differ at some D on the paper's ground); their spread is reported.
PHASES = (0.0, TWO_PI / 3, 2 * TWO_PI / 3)
FORE, MIDDLE, HIND = (0, 1), (2, 3), (4, 5)  # paper legs 1-2, 3-4, 5-6 (0-based)
# The fore's bump is looked for below this D (rad): above it the tripod side's own features.
BUMP_MAX_D = 2.6
# The hind's baseline: its median jump this far (rad) and more above L_DW, where no neighbour
# lifts off during its swing.
BASELINE_GAP = 0.2


def l_dw(beta: float) -> float:
    """D where a posterior leg lands as its anterior neighbour lifts off: 2 pi (1 - beta)."""
    return TWO_PI * (1.0 - beta)


def l_fh(beta: float) -> float:
    """D where a fore leg lands as its ipsilateral hind leg lifts off: pi beta."""
    return math.pi * beta


def omega(beta: float, swing_duration: float = ModelParams().trajectory.swing_duration) -> float:
    """Oscillator frequency at beta (eq. 2: the swing lasts T_sw, a (1 - beta) share), rad/s."""
    return TWO_PI * (1.0 - beta) / swing_duration


@dataclass
class OpenLoop:
    """Mean phase jump per leg pair against the held D, per beta (rad; > 0 lands early)."""

    ground: str
    betas: list[float]
    d31s: list[float]
    fore: np.ndarray  # (nb, nd)
    middle: np.ndarray
    hind: np.ndarray
    spread: np.ndarray  # (nb, nd): largest std over the PHASES starts of any pair's jump


def open_loop_legs(
    params: ModelParams,
    betas: Sequence[float],
    d31s: Sequence[float],
    *,
    duration_s: float = 4.0,
    settle_s: float = 1.0,
    phases: Sequence[float] = PHASES,
    nthread: int = 0,
    progress: Callable[[float], None] | None = None,
) -> OpenLoop:
    """Test 1: the pairs' phase jumps with resets off and D held (one batch of every probe)."""
    specs = [RunSpec(beta=b, d31_init=float(d) % TWO_PI, duration_s=duration_s,
                     phase_reset=False, phi1_init=p)
             for b in betas for d in d31s for p in phases]  # fmt: skip
    results = simulate_batch(specs, params, nthread=nthread, progress=progress)
    jumps = np.full((len(specs), 6), np.nan)
    for k, (s, r) in enumerate(zip(specs, results, strict=True)):
        if not r.diverged:
            jumps[k] = phase_jumps(
                r.events.touchdowns_s, r.events.touchdown_phases, phi_aep(s.beta), settle_s
            )
    j = jumps.reshape(len(betas), len(d31s), len(phases), 6)

    def pair(legs: tuple[int, int]) -> np.ndarray:
        return np.asarray(np.nanmean(j[..., list(legs)], axis=(2, 3)))

    per_pair = np.stack([np.nanmean(j[..., list(p)], axis=3) for p in (FORE, MIDDLE, HIND)])
    spread = np.nanmax(np.nanstd(per_pair, axis=3), axis=0)
    return OpenLoop(params.contact.ground, list(betas), [float(d) for d in d31s], pair(FORE),
                    pair(MIDDLE), pair(HIND), spread)  # fmt: skip


def edge(d: np.ndarray, e: np.ndarray, baseline: float) -> float | None:
    """Where a ramp that is high at low D falls to half way between its peak and `baseline`
    for the last time, going up in D (linear interpolation); None if it never rises."""
    ok = np.isfinite(e)
    d, e = d[ok], e[ok]
    if d.size < 2:
        return None
    peak = float(e.max())
    if peak <= baseline:
        return None
    half = 0.5 * (peak + baseline)
    above = np.nonzero(e >= half)[0]
    k = int(above[-1])
    if k + 1 >= d.size:
        return None
    x0, x1, y0, y1 = d[k], d[k + 1], e[k], e[k + 1]
    return float(x0 + (half - y0) * (x1 - x0) / (y1 - y0)) if y1 != y0 else float(x0)


@dataclass
class Features:
    """What test 1 reads at one beta (rad and mrad)."""

    ground: str
    beta: float
    l_dw: float
    hind_edge: float | None  # where the hind's early-landing ramp ends
    lag_ms: float | None  # (L_DW - hind_edge) / omega: the lag the push acts with
    l_fh: float
    fore_bump_d: float | None  # D of the fore's largest early bump below BUMP_MAX_D
    fore_bump_mrad: float | None  # its height above the fore's baseline
    fore_edge: float | None  # where that bump ends, going up in D
    spread_mrad: float  # the largest spread over the PHASES starts (how jagged the curves are)


def features(ol: OpenLoop) -> list[Features]:
    d = np.asarray(ol.d31s)
    out = []
    for i, b in enumerate(ol.betas):
        hind, fore = ol.hind[i], ol.fore[i]
        base_h = float(np.nanmedian(hind[d >= l_dw(b) + BASELINE_GAP])) if np.any(
            d >= l_dw(b) + BASELINE_GAP) else float(np.nanmin(hind))  # fmt: skip
        h_edge = edge(d, hind, base_h)
        window = d <= BUMP_MAX_D
        base_f = float(np.nanmedian(fore[window]))
        bump = fore[window] - base_f
        k = int(np.nanargmax(bump)) if np.any(np.isfinite(bump)) else None
        f_edge = None
        if k is not None:
            f_edge = edge(d[window][k:], fore[window][k:], base_f)
        out.append(Features(
            ol.ground, b, l_dw(b), h_edge,
            None if h_edge is None else 1e3 * (l_dw(b) - h_edge) / omega(b),
            l_fh(b), None if k is None else float(d[window][k]),
            None if k is None else 1e3 * float(bump[k]), f_edge,
            1e3 * float(np.nanmax(ol.spread[i])),
        ))  # fmt: skip
    return out


@dataclass
class ChainLag:
    """Test 2 on one closed-loop run: middle lift-off -> ipsilateral hind touchdown, in ms."""

    ground: str
    beta: float
    d31_init: float
    final: float | None  # settled Delta31 (None: not settled)
    lag_ms: float | None  # median over the run's last half, both sides
    hind_early_ms: float | None  # median of how early the hind lands (phase jump / omega)
    lags: list[float] = field(default_factory=list)


def chain_lags(
    params: ModelParams,
    runs: Sequence[tuple[float, float]],
    *,
    duration_s: float = 30.0,
    nthread: int = 0,
) -> list[ChainLag]:
    """Test 2: closed-loop runs (beta, start); per hind touchdown in the last half, the time
    since its ipsilateral middle leg last lifted off (when that lift-off fell in its swing)."""
    specs = [RunSpec(beta=b, d31_init=x, duration_s=duration_s) for b, x in runs]
    out = []
    for s, r in zip(specs, simulate_batch(specs, params, nthread=nthread), strict=True):
        if r.diverged:
            out.append(ChainLag(params.contact.ground, s.beta, s.d31_init, None, None, None))
            continue
        st = settling(r.events.d31)
        lags: list[float] = []
        early: list[float] = []
        w = omega(s.beta, params.trajectory.swing_duration)
        for hind, mid in ((4, 2), (5, 3)):
            tds, phs = r.events.touchdowns_s[hind], r.events.touchdown_phases[hind]
            lifts = np.asarray(r.events.liftoffs_s[mid])
            hind_lifts = np.asarray(r.events.liftoffs_s[hind])
            for t, ph in zip(tds, phs, strict=True):
                if t < duration_s / 2:
                    continue
                own = hind_lifts[hind_lifts < t]
                prior = lifts[lifts < t]
                if own.size and prior.size and prior[-1] > own[-1]:  # during the hind's swing
                    lags.append(1e3 * float(t - prior[-1]))
                early.append(1e3 * float((phi_aep(s.beta) - ph) / w))
        out.append(ChainLag(
            params.contact.ground, s.beta, s.d31_init, st.final if st.settled else None,
            float(np.median(lags)) if lags else None,
            float(np.median(early)) if early else None, lags,
        ))  # fmt: skip
    return out


@dataclass
class ReducedBranch:
    """Test 3 at one (beta, leg lag): the settled states of the reduced model's starts."""

    beta: float
    lag_ms: float  # c/k of its legs
    finals: list[float]  # settled states, rad (rounded clusters)
    unsettled: int


def reduced_branches(
    betas: Sequence[float],
    lags_ms: Sequence[float],
    *,
    starts: Sequence[float] = (1.6, 1.9, 2.2, 2.5, 3.0),
    duration_s: float = 40.0,
) -> list[ReducedBranch]:
    """Test 3: the reduced model (equal legs) from `starts` at each beta and leg lag."""
    base = ReducedParams()
    out = []
    for lag in lags_ms:
        p = replace(base, leg_damping=base.leg_stiffness * lag * 1e-3)
        for b in betas:
            finals: list[float] = []
            unsettled = 0
            for x in starts:
                try:
                    run = run_reduced(b, x, duration_s=duration_s, params=p)
                except FloatingPointError:
                    unsettled += 1
                    continue
                s = settling(run.d31)
                if s.settled and s.final is not None:
                    if all(abs(s.final - f) > 0.05 for f in finals):
                        finals.append(round(s.final, 3))
                else:
                    unsettled += 1
            out.append(ReducedBranch(b, lag, sorted(finals), unsettled))
    return out


# --- the report: tables and a figure (the `python -m lab timing-lines` command) -------------
def _f(x: float | None, fmt: str = "{:.2f}") -> str:
    return "–" if x is None else fmt.format(x)


def features_table(rows: Sequence[Features]) -> list[str]:
    out = ["| ground | β | L_DW | hind ramp ends | lag (ms) | L_FH | fore bump at D | height "
           "(mrad) | bump ends | spread over starts (mrad) |",
           "|---|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in rows:
        out.append(f"| {r.ground} | {r.beta:g} | {r.l_dw:.2f} | {_f(r.hind_edge)} | "
                   f"{_f(r.lag_ms, '{:.1f}')} | {r.l_fh:.2f} | {_f(r.fore_bump_d)} | "
                   f"{_f(r.fore_bump_mrad, '{:.0f}')} | {_f(r.fore_edge)} | "
                   f"{r.spread_mrad:.0f} |")  # fmt: skip
    return out


def chain_table(rows: Sequence[ChainLag]) -> list[str]:
    out = ["| ground | β | start | settled at | middle lift-off → hind touchdown (ms, median) | "
           "hind lands early by (ms, median) | L_DW − D at the state (ms) |",
           "|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in rows:
        gap = None if r.final is None else 1e3 * (l_dw(r.beta) - r.final) / omega(r.beta)
        out.append(f"| {r.ground} | {r.beta:g} | {r.d31_init:g} | {_f(r.final, '{:.3f}')} | "
                   f"{_f(r.lag_ms, '{:.1f}')} | {_f(r.hind_early_ms, '{:.1f}')} | "
                   f"{_f(gap, '{:.1f}')} |")  # fmt: skip
    return out


def reduced_table(rows: Sequence[ReducedBranch]) -> list[str]:
    out = ["| leg lag c/k (ms) | β | settled states | min(L_DW − ωτ, L_FH) | not settled |",
           "|---|---|---|---|---|"]  # fmt: skip
    for r in rows:
        line = min(l_dw(r.beta) - omega(r.beta) * r.lag_ms * 1e-3, l_fh(r.beta))
        states = ", ".join(f"{x:.3f}" for x in r.finals) or "none"
        out.append(f"| {r.lag_ms:g} | {r.beta:g} | {states} | {line:.2f} | {r.unsettled} |")
    return out


def plot_open_loop(loops: Sequence[OpenLoop], path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    nb = max(len(o.betas) for o in loops)
    fig, axes = plt.subplots(len(loops), nb, figsize=(4.2 * nb, 3.4 * len(loops)),
                             squeeze=False, sharex=True)  # fmt: skip
    for row, ol in zip(axes, loops, strict=True):
        for ax, (i, b) in zip(row, enumerate(ol.betas), strict=False):
            d = np.asarray(ol.d31s)
            ax.plot(d, 1e3 * ol.hind[i], "-o", ms=2.5, label="hind (e5, e6)")
            ax.plot(d, 1e3 * ol.fore[i], "-o", ms=2.5, label="fore (e1, e2)")
            ax.plot(d, 1e3 * ol.middle[i], "-", lw=0.8, color="0.6", label="middle")
            ax.axvline(l_dw(b), color="tab:blue", ls="--", lw=0.8)
            ax.axvline(l_fh(b), color="tab:orange", ls="--", lw=0.8)
            ax.text(l_dw(b), ax.get_ylim()[1], " L_DW", color="tab:blue", fontsize=7, va="top")
            ax.text(l_fh(b), ax.get_ylim()[0], " L_FH", color="tab:orange", fontsize=7)
            ax.set_title(f"{ol.ground} ground, β = {b:g}", fontsize=9)
            ax.axhline(0, color="k", lw=0.5)
        row[0].set_ylabel("phase jump at touchdown (mrad; > 0 early)")
    for ax in axes[-1]:
        ax.set_xlabel("held D = Δ31 = Δ53 (rad), resets off")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)

"""Issue 30, point 5: does the body keep walking up or down a slope, or does it turn?

On the constraint ground a downhill run at -20 deg turned 1, 10, 28 and 100 deg by 10, 20, 30
and 40 s (from Delta31 1.9, beta 0.66), while the paper's ground held within 1 deg: a turned
body makes "uphill" meaningless for Fig. 9b. `headings` runs the slopes x starts x settings
asked for and reports the body's heading (`gait.yaw_of` of the recorded orientation) at given
times, the final Delta31 and the foot slip, so a candidate fix is judged by one table.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sim_core import ModelParams, RunSpec, simulate_batch
from sim_core.contract import settling
from sim_core.research import HEADING_KEPT_DEG, yaw_of


@dataclass
class HeadingRun:
    setting: str
    slope_deg: float
    d31_init: float
    headings_deg: list[float | None]  # at the asked times (None: the run had ended)
    final: float | None  # settled Delta31 (None: not settled)
    slip: float | None
    failure: str | None

    @property
    def holds(self) -> bool:
        return self.failure is None and all(
            h is not None and abs(h) <= HEADING_KEPT_DEG for h in self.headings_deg
        )


def headings(
    settings: Sequence[tuple[str, ModelParams]],
    slopes_deg: Sequence[float] = (-20.0, 20.0),
    starts: Sequence[float] = (1.9, 3.0),
    *,
    beta: float = 0.66,
    duration_s: float = 60.0,
    at_s: Sequence[float] = (10.0, 20.0, 30.0, 40.0, 50.0, 60.0),
    nthread: int = 0,
) -> list[HeadingRun]:
    """Every (setting, slope, start): the heading at `at_s`, deg from the slope's +x."""
    out = []
    for name, p in settings:
        specs = [RunSpec(beta=beta, slope_deg=s, d31_init=x, duration_s=duration_s)
                 for s in slopes_deg for x in starts]  # fmt: skip
        for spec, r in zip(specs, simulate_batch(specs, p, nthread=nthread), strict=True):
            hs: list[float | None] = []
            t = r.series.times_s
            for a in at_s:
                if t.size == 0 or a > t[-1] + 1e-9:
                    hs.append(None)
                    continue
                k = int(np.searchsorted(t, a - 1e-9))
                hs.append(math.degrees(float(yaw_of(r.series.body_quat[min(k, t.size - 1)]))))
            st = settling(r.events.d31) if r.failure is None else None
            out.append(HeadingRun(name, spec.slope_deg, spec.d31_init, hs,
                                  st.final if st is not None and st.settled else None,
                                  r.measures.slip_fraction, r.error))  # fmt: skip
    return out


def table(runs: Sequence[HeadingRun], at_s: Sequence[float]) -> list[str]:
    head = " / ".join(f"{a:g}" for a in at_s)
    rows = [f"| setting | slope (deg) | start | heading (deg) at {head} s | final Δ31 | slip "
            f"| within {HEADING_KEPT_DEG:g} deg |", "|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in runs:
        hs = " / ".join("–" if h is None else f"{h:.1f}" for h in r.headings_deg)
        fin = "not settled" if r.final is None else f"{r.final:.2f}"
        slip = "–" if r.slip is None else f"{100 * r.slip:.1f}%"
        ok = "yes" if r.holds else ("**no**" if r.failure is None else f"failed: {r.failure}")
        rows.append(f"| {r.setting} | {r.slope_deg:+g} | {r.d31_init:g} | {hs} | {fin} | "
                    f"{slip} | {ok} |")  # fmt: skip
    return rows

"""The return map on viser's uPlot: Delta31(n) against Delta31(n + lag), newer pairs darker.

The one chart that fits uPlot as viser 1.1 exposes it (JSON options, aligned 1-D series): a
scatter with a dashed diagonal and age shading, no labels inside the plot. It costs the page
about what the SVG did (benchmarks/chart_cost.py: 6.7 against 7.8 ms a redraw of 1 200 points)
and gives a cursor that reads the pair under it. The other charts stay SVG (docs/VIEWER.md,
"Why the charts stay SVG, but the return map").

uPlot's aligned mode shares one ascending x array among its series, so the pairs are sorted by
Delta31(n), and each age group is a series that holds its own pairs' Delta31(n + lag) and NaN
(not drawn) elsewhere; the diagonal runs over the whole axis, a little past 0 and 2 pi.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import viser

from sim_core.contract import TWO_PI
from web.svg import MAX_DRAWN

RECENCY_SHADES = 6  # age groups of equal size, the oldest faintest
LAG = 4  # Delta31(n) -> Delta31(n + 4): one pair per gait cycle of the four-beat record
TICKS = (0.0, TWO_PI / 3, math.pi, TWO_PI)
TICK_LABELS = ("0", "2π/3", "π", "2π")
TITLE = f"Return map: Δ31(n) → Δ31(n+{LAG})"


def _shade(k: int) -> str:
    return f"rgba(34,34,34,{0.15 + 0.85 * (k + 1) / RECENCY_SHADES:.2f})"


SERIES: tuple[Any, ...] = (
    {"label": "Δ31(n) (rad)"},
    {"label": "diagonal", "stroke": "#999", "width": 1, "dash": (3, 2), "points": {"show": False}},
    *(
        {"label": f"age group {k + 1} of {RECENCY_SHADES} (newest last)", "stroke": _shade(k),
         "width": 0, "points": {"show": True, "size": 3, "fill": _shade(k), "width": 0}}
        for k in range(RECENCY_SHADES)
    ),
)  # fmt: skip
AXES: tuple[Any, ...] = (
    {"label": "Δ31(n) (rad)", "splits": TICKS, "values": TICK_LABELS},
    {"label": f"Δ31(n+{LAG}) (rad)", "splits": TICKS, "values": TICK_LABELS},
)
# the axes reach a little past 0 and 2 pi, so that the end ticks' labels are not cut (viser
# ranges x from the data, so the diagonal's ends are there)
EDGE = 0.2
SCALES: dict[str, Any] = {
    "x": {"time": False, "range": (-EDGE, TWO_PI + EDGE)},
    "y": {"range": (-EDGE, TWO_PI + EDGE)},
}


def return_map_data(pairs: Sequence[tuple[float, float]]) -> tuple[np.ndarray, ...]:
    """uPlot's aligned data for the latest MAX_DRAWN pairs: (x sorted, the diagonal, one
    column per age group with NaN where the pair is another group's)."""
    shown = np.asarray(list(pairs)[-MAX_DRAWN:], dtype=float).reshape(-1, 2)
    n = len(shown)
    age = np.zeros(n, dtype=int)
    for k, group in enumerate(np.array_split(np.arange(n), RECENCY_SHADES)):
        age[group] = k
    order = np.argsort(shown[:, 0], kind="stable")
    x = np.concatenate(([-EDGE], shown[order, 0], [TWO_PI + EDGE]))  # the diagonal's ends
    columns = []
    for k in range(RECENCY_SHADES):
        column = np.full(n + 2, np.nan)
        mine = age[order] == k
        column[1:-1][mine] = shown[order, 1][mine]
        columns.append(column)
    return (x, x.copy(), *columns)


def add_return_map(gui: viser.GuiApi) -> viser.GuiUplotHandle:
    """The panel, empty until the first pairs (the diagonal only)."""
    return gui.add_uplot(
        return_map_data([]),
        SERIES,
        title=TITLE,
        scales=SCALES,
        axes=AXES,
        legend={"show": False},
        aspect=1.25,
    )

"""What every chart of the panels shares, as small inline SVG strings (viser shows them with
`gui.add_html`).

SVG rather than a plotting widget because the footfall diagram is bars, not lines: each stance
interval is one <rect>, coloured per leg pair, and nothing has to be encoded as gaps in a series.
The functions are pure (numbers in, markup out), so a test can check what a browser will draw.

Here: the viewBox and its margins (`Frame`), a panel's opening (`open_svg`), the axes and
ticks, the gaits' reference lines, many dots as one path, the legend under the ticks and a note
across the plot; one definition of each, so that every panel reads alike. The charts are one
module per family, built from these: web/footfall_svg.py, web/d31_svg.py (the Delta31 history
and its marks), web/bifurcation_svg.py (the finder's states and a ramp's path),
web/atlas_svg.py, web/surface_svg.py; the return map is uPlot's (web/return_map_plot.py).
"""

from __future__ import annotations

import html
import itertools
import math
import re
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass

from sim_core.contract import TWO_PI

W, H = 300, 150  # viewBox; the panel scales it to its width
LEFT, RIGHT, TOP, BOTTOM = 34, 14, 16, 20
FONT = 'font-family="sans-serif" font-size="9"'


@dataclass(frozen=True)
class Frame:
    """Maps data coordinates into the plot area of a `w` x `h` viewBox."""

    x0: float
    x1: float
    y0: float
    y1: float
    w: float = W
    h: float = H
    legend_h: float = 0.0  # room under the ticks for a legend

    def x(self, v: float) -> float:
        span = self.x1 - self.x0 or 1.0
        return LEFT + (v - self.x0) / span * (self.w - LEFT - RIGHT)

    def y(self, v: float) -> float:
        span = self.y1 - self.y0 or 1.0
        return self.bottom - (v - self.y0) / span * (self.bottom - TOP)

    @property
    def bottom(self) -> float:
        """The plot area's lower edge; below it the ticks (and a legend, for taller panels)."""
        return self.h - BOTTOM - self.legend_h

    @property
    def right(self) -> float:
        """The plot area's right edge."""
        return self.w - RIGHT


def dots(
    points: Sequence[tuple[float, float]],
    r: float,
    colour: str,
    opacity: float = 1.0,
    cls: str = "dots",
) -> str:
    """Many dots as ONE path element (a zero-length stroke with round caps per point): a browser
    lays out and paints one node instead of one <circle> per point, which is what kept a
    software-rendered page's main thread busy when 1 200 of them were redrawn 5 times a second.
    `data-n` says how many dots it holds."""
    d = "".join(f"M{x:.1f},{y:.1f}h0" for x, y in points)
    return (
        f'<path class="{cls}" data-n="{len(points)}" d="{d}" fill="none" stroke="{colour}" '
        f'stroke-opacity="{opacity:.2f}" stroke-width="{2 * r:g}" stroke-linecap="round"/>'
    )


def n_dots(svg: str, cls: str = "dots") -> int:
    """How many dots the `dots` paths of class `cls` in `svg` hold (for tests and probes)."""
    return sum(int(n) for n in re.findall(f'class="{cls}" data-n="(\\d+)"', svg))


def open_svg(
    kind: str, title: str, *, w: float = W, h: float = H, legend_h: float = 0.0, **attrs: str
) -> list[str]:
    """The panel's frame. Its width on the page is w / W of the panel's, so that every panel
    draws its text at one size whatever its viewBox (a narrower one is not blown up)."""
    extra = "".join(f' data-{k.replace("_", "-")}="{html.escape(v)}"' for k, v in attrs.items())
    bottom = h - BOTTOM - legend_h
    return [
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {w} {h}" '
        f'width="{100 * min(1.0, w / W):.0f}%" '
        f'data-plot="{kind}"{extra} style="background:#fff">',
        f'<text x="{LEFT}" y="11" {FONT} font-weight="bold">{html.escape(title)}</text>',
        f'<rect x="{LEFT}" y="{TOP}" width="{w - LEFT - RIGHT}" height="{bottom - TOP}" '
        'fill="none" stroke="#999" stroke-width="0.5"/>',
    ]


def time_window(t_now: float, window_s: float) -> tuple[float, float]:
    """The scrolling plots' time axis: [0, window] until the run is that old, then the last
    `window_s` (never a negative time: the run starts at 0)."""
    t1 = max(t_now, window_s)
    return t1 - window_s, t1


def _axis_label(f: Frame, text: str) -> str:
    """What the x ticks count, in the free corner left of the axis."""
    return (
        f'<text x="{LEFT - 3}" y="{f.bottom + 11}" {FONT} text-anchor="end" '
        f'fill="#666">{html.escape(text)}</text>'
    )


def time_axis_label(f: Frame) -> str:
    return _axis_label(f, "t (s)")


def x_ticks(f: Frame, ticks: Sequence[float], fmt: str) -> list[str]:
    out = []
    for v in ticks:
        x = f.x(v)
        out.append(
            f'<line x1="{x:.1f}" y1="{f.bottom}" x2="{x:.1f}" y2="{f.bottom + 3}" '
            'stroke="#999" stroke-width="0.5"/>'
        )
        out.append(
            f'<text x="{x:.1f}" y="{f.bottom + 11}" {FONT} text-anchor="middle">'
            f"{fmt.format(v)}</text>"
        )
    return out


def y_angle_axis(f: Frame) -> list[str]:
    out = []
    for v, label in ((0.0, "0"), (TWO_PI / 3, "2π/3"), (math.pi, "π"), (TWO_PI, "2π")):
        out.append(
            f'<text x="{LEFT - 3}" y="{f.y(v) + 3:.1f}" {FONT} text-anchor="end">{label}</text>'
        )
    return out


def reference_lines(f: Frame) -> list[str]:
    """Tripod (pi) and metachronal (2 pi / 3) gaits, as in the paper's figures."""
    out = []
    for v, colour, name in ((math.pi, "#d62728", "tripod"), (TWO_PI / 3, "#1f77b4", "metachr.")):
        y = f.y(v)
        out.append(
            f'<line x1="{LEFT}" y1="{y:.1f}" x2="{f.w - RIGHT}" y2="{y:.1f}" stroke="{colour}" '
            'stroke-width="0.7" stroke-dasharray="4 3"/>'
        )
        out.append(
            f'<text x="{f.w - RIGHT - 2}" y="{y - 2:.1f}" {FONT} fill="{colour}" '
            f'text-anchor="end">{name}</text>'
        )
    return out


def time_ticks(t0: float, t1: float) -> list[float]:
    span = t1 - t0
    steps = (0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0)
    step = next((s for s in steps if span / s <= 6), 1000.0)
    first = math.ceil(t0 / step) * step
    n = int((t1 - first) / step + 1e-9) + 1
    return [first + i * step for i in range(max(0, n))]


# Drawn at most this many Delta31 points: the whole run is kept (`Simulation.d31_events`), but a
# 10-minute run has ~6000 touchdowns and the panel is redrawn 5 times a second for every browser.
MAX_DRAWN = 1200

LEGEND_H = 48.0  # up to four legend rows under the ticks (a long row wraps: `legend`)
BIF_H = H + LEGEND_H


def legend(f: Frame, rows: Sequence[Sequence[tuple[str, str]]]) -> list[str]:
    """Legend rows under the x ticks: (markup of a symbol + words, colour) each, left to right.
    Below the plot so it never covers data or the gait lines' labels."""
    out = []
    r = -1
    for row in rows:
        r, x = r + 1, float(LEFT)
        for text, colour in row:
            width = 5.2 * len(html.unescape(text))
            if x > LEFT and x + width > f.w - 2:  # the row would leave the panel: wrap
                r, x = r + 1, float(LEFT)
            y = f.bottom + 22 + 11 * r
            out.append(f'<text x="{x:.0f}" y="{y:.0f}" {FONT} fill="{colour}">{text}</text>')
            x += width + 10
    return out


def plot_note(f: Frame, note: str, width: int = 52) -> str:
    """A note across the plot area (a missing or invalid file), wrapped to the plot's width;
    the whole text is also the element's tooltip."""
    lines = textwrap.wrap(note, width)[:3] or [""]
    if len(lines) == 3 and len(" ".join(lines)) < len(note):
        lines[2] = lines[2][: width - 3] + "..."
    x = (LEFT + f.w - RIGHT) / 2
    y0 = f.bottom - 6 - 11 * (len(lines) - 1)
    spans = "".join(
        f'<tspan x="{x:.0f}" y="{y0 + 11 * k:.0f}">{html.escape(line)}</tspan>'
        for k, line in enumerate(lines)
    )
    return (
        f'<text class="note" {FONT} fill="#a00" text-anchor="middle">'
        f"<title>{html.escape(note)}</title>{spans}</text>"
    )


def cell_edges(centres: Sequence[float]) -> list[float]:
    """Cell edges around sorted grid values: halfway between neighbours, half a step outside."""
    c = list(centres)
    if len(c) == 1:
        return [c[0] - 0.5, c[0] + 0.5]
    mids = [(a + b) / 2 for a, b in itertools.pairwise(c)]
    return [c[0] - (mids[0] - c[0]), *mids, c[-1] + (c[-1] - mids[-1])]

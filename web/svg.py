"""What every chart of the panels shares, as small inline SVG strings (viser shows them with
`gui.add_html`).

SVG rather than a plotting widget because the footfall diagram is bars, not lines: each stance
interval is one <rect>, coloured per leg pair, and nothing has to be encoded as gaps in a series.
The functions are pure (numbers in, markup out), so a test can check what a browser will draw.

Here: the viewBox and its margins (`Frame`, `panel_frame`), a panel's opening and title
(`open_svg`, two lines where one would be cut), the axes, ticks and axis words, the gaits'
reference lines, many dots as one path and a note across the plot; one definition of each, so
that every panel reads alike, with the widths the layout counts text at (`CHAR_W`). The legend
is web/legend_svg.py's, the paper's numbers web/paper_svg.py's. The charts are one module per
family, built from these: web/footfall_svg.py, web/d31_svg.py (the Delta31 history and its
marks), web/bifurcation_svg.py (the finder's states and a ramp's path), web/atlas_svg.py,
web/surface_svg.py; the return map is uPlot's (web/return_map_plot.py).
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
LINE = 11.0  # px from one line of 9 px text to the next (a line's glyphs are ~8.6 px tall)
TICK_Y = 12.0  # the x ticks' baseline under the plot: clear of a y tick at the plot's foot
TITLE_X = 4.0  # the title starts at the panel's left edge: the whole width is its line
# The widths the layout counts with, per character of the 9 px font. Measured in headless
# Chromium (DejaVu Sans, the "sans-serif" of the browser tests): a short label reaches 0.69 em
# a character ("π"; "○ now" 0.60), a sentence averages less (0.61 em at most, bold titles
# 0.54), so a label counts 0.7 em, a note wraps at 0.62 em and a bold title at 0.62 x 1.1.
CHAR_W = 6.3
LONG_CHAR_W = 5.6
TITLE_CHAR_W = 6.2
TITLE_Y = 10.0  # the title's baseline: its line clears the top y tick's (at TOP + 3)


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
    top: float = TOP  # the plot area's upper edge (lower when the title takes two lines)

    def x(self, v: float) -> float:
        span = self.x1 - self.x0 or 1.0
        return LEFT + (v - self.x0) / span * (self.w - LEFT - RIGHT)

    def y(self, v: float) -> float:
        span = self.y1 - self.y0 or 1.0
        return self.bottom - (v - self.y0) / span * (self.bottom - self.top)

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


def title_lines(title: str, w: float = W) -> list[str]:
    """The title on as few lines as the panel's width allows (two at most: a title that names
    the conditions in force is long, and a clipped one hides them)."""
    lines = textwrap.wrap(title, int((w - 2 * TITLE_X) / TITLE_CHAR_W)) or [""]
    return [lines[0], " ".join(lines[1:])] if len(lines) > 2 else lines


def panel_frame(
    title: str, x0: float, x1: float, y0: float, y1: float, *, below: float = 0.0, w: float = W
) -> Frame:
    """The frame of a panel titled `title` with `below` px of rows under the x ticks (a legend,
    an axis word): the plot area keeps its height, the viewBox grows by what the title's second
    line and the rows take."""
    extra = LINE * (len(title_lines(title, w)) - 1)
    return Frame(x0, x1, y0, y1, w=w, h=H + below + extra, legend_h=below, top=TOP + extra)


def open_svg(kind: str, title: str, f: Frame, **attrs: str) -> list[str]:
    """The panel's opening, title and plot box, in the frame `panel_frame` made for `title`.
    Its width on the page is w / W of the panel's, so that every panel draws its text at one
    size whatever its viewBox (a narrower one is not blown up)."""
    extra = "".join(f' data-{k.replace("_", "-")}="{html.escape(v)}"' for k, v in attrs.items())
    heading = "".join(
        f'<tspan x="{TITLE_X:g}" y="{TITLE_Y + LINE * k:g}">{html.escape(line)}</tspan>'
        for k, line in enumerate(title_lines(title, f.w))
    )
    return [
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {f.w:g} {f.h:g}" '
        f'width="{100 * min(1.0, f.w / W):.0f}%" '
        f'data-plot="{kind}"{extra} style="background:#fff">',
        f'<text class="title" {FONT} font-weight="bold">{heading}</text>',
        f'<rect x="{LEFT}" y="{f.top:g}" width="{f.w - LEFT - RIGHT:g}" '
        f'height="{f.bottom - f.top:g}" fill="none" stroke="#999" stroke-width="0.5"/>',
    ]


def time_window(t_now: float, window_s: float) -> tuple[float, float]:
    """The scrolling plots' time axis: [0, window] until the run is that old, then the last
    `window_s` (never a negative time: the run starts at 0)."""
    t1 = max(t_now, window_s)
    return t1 - window_s, t1


def axis_word(f: Frame, text: str) -> str:
    """What the x ticks count, centred under them on a row of its own (`below=LINE`): beside
    the first tick it printed over it."""
    return (
        f'<text class="axis-word" x="{(LEFT + f.right) / 2:.1f}" y="{f.bottom + TICK_Y + LINE:g}" '
        f'{FONT} text-anchor="middle" fill="#666">{html.escape(text)}</text>'
    )


def time_axis_word(f: Frame) -> str:
    return axis_word(f, "t (s)")


def x_ticks(f: Frame, ticks: Sequence[float], fmt: str) -> list[str]:
    out = []
    for v in ticks:
        x = f.x(v)
        out.append(
            f'<line x1="{x:.1f}" y1="{f.bottom}" x2="{x:.1f}" y2="{f.bottom + 3}" '
            'stroke="#999" stroke-width="0.5"/>'
        )
        out.append(
            f'<text x="{x:.1f}" y="{f.bottom + TICK_Y}" {FONT} text-anchor="middle">'
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

NOTE_LINES = 5
REF_LABEL_W = 56.0  # the gait lines' labels at the plot's right edge ("metachr.")


def plot_note(f: Frame, note: str) -> str:
    """A note across the plot area (a missing or invalid file), wrapped to the plot's width
    left of the gait lines' labels, at most NOTE_LINES lines (cut with "..."); the whole
    text is also the element's tooltip."""
    right = f.right - REF_LABEL_W
    width = int((right - LEFT - 4) / LONG_CHAR_W)
    lines = textwrap.wrap(note, width)[:NOTE_LINES] or [""]
    if len(lines) == NOTE_LINES and len(" ".join(lines)) < len(note):
        lines[-1] = lines[-1][: width - 3] + "..."
    x = (LEFT + right) / 2
    y0 = f.bottom - 6 - LINE * (len(lines) - 1)
    spans = "".join(
        f'<tspan x="{x:.0f}" y="{y0 + LINE * k:.0f}">{html.escape(line)}</tspan>'
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

"""The panels' diagrams as small inline SVG strings (viser shows them with `gui.add_html`).

SVG rather than a plotting widget because the footfall diagram is bars, not lines: each stance
interval is one <rect>, coloured per leg pair, and nothing has to be encoded as gaps in a series.
The functions are pure (numbers in, markup out), so a test can check what a browser will draw.
"""

from __future__ import annotations

import html
import itertools
import math
import re
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sim_core.contract import LEG_NAMES, TWO_PI, SurfaceAtlas
from web.bifurcation import FinderPoints
from web.record import CoreEvents, D31Event, Mark

LEG_ORDER = LEG_NAMES  # the paper's legs 1-6, rows top to bottom
# Fig. 4's colouring by leg pair: fore (legs 1-2) red, middle (3-4) blue, hind (5-6) green;
# right legs in the full colour, left legs in a light tint of it, so that both the pair and the
# side read at a glance: a tripod is a checkerboard (R1 L2 R3 against L1 R2 L3), a metachronal
# wave a staircase running from hind to fore on each side.
PAIR_COLOURS = ("#d62728", "#1f77b4", "#2ca02c")
PAIR_NAMES = ("fore", "middle", "hind")
LEFT_TINTS = ("#f1a3a4", "#9cc7e8", "#9fdc9f")
LEG_COLOURS = tuple(PAIR_COLOURS[i // 2] if i % 2 == 0 else LEFT_TINTS[i // 2] for i in range(6))

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


def _open(
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


def _time_axis_label(f: Frame) -> str:
    return _axis_label(f, "t (s)")


def _x_ticks(f: Frame, ticks: Sequence[float], fmt: str) -> list[str]:
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


def _y_angle_axis(f: Frame) -> list[str]:
    out = []
    for v, label in ((0.0, "0"), (TWO_PI / 3, "2π/3"), (math.pi, "π"), (TWO_PI, "2π")):
        out.append(
            f'<text x="{LEFT - 3}" y="{f.y(v) + 3:.1f}" {FONT} text-anchor="end">{label}</text>'
        )
    return out


def _reference_lines(f: Frame) -> list[str]:
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


def _time_ticks(t0: float, t1: float) -> list[float]:
    span = t1 - t0
    steps = (0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0)
    step = next((s for s in steps if span / s <= 6), 1000.0)
    first = math.ceil(t0 / step) * step
    n = int((t1 - first) / step + 1e-9) + 1
    return [first + i * step for i in range(max(0, n))]


def footfall_svg(
    bars: Sequence[Sequence[tuple[float, float]]], t_now: float, window_s: float
) -> str:
    """Six rows (legs 1-6: R1 L1 R2 L2 R3 L3), one rect per stance interval, scrolling."""
    t0, t1 = time_window(t_now, window_s)
    f = Frame(t0, t1, 0.0, 6.0)
    out = _open(
        "footfall",
        f"Footfall, last {window_s:g} s (bar = stance; right dark, left light)",
        t_now=f"{t_now:.4f}",
        window_s=f"{window_s:g}",
    )
    row_h = (H - TOP - BOTTOM) / 6.0
    n_bars = 0
    for pair in (1, 2):  # thin lines between fore, middle and hind
        y = TOP + 2 * pair * row_h
        out.append(
            f'<line x1="{LEFT}" y1="{y:.1f}" x2="{W - RIGHT}" y2="{y:.1f}" stroke="#ccc" '
            'stroke-width="0.5"/>'
        )
    for leg, legbars in enumerate(bars):
        y = TOP + leg * row_h
        out.append(
            f'<text x="{LEFT - 3}" y="{y + row_h * 0.7:.1f}" {FONT} text-anchor="end" '
            f'fill="{PAIR_COLOURS[leg // 2]}">{leg + 1} {LEG_ORDER[leg]}</text>'
        )
        for a, b in legbars:
            a, b = max(a, t0), min(b, t1)
            if b <= a:
                continue
            n_bars += 1
            out.append(
                f'<rect class="stance" data-leg="{LEG_ORDER[leg]}" x="{f.x(a):.2f}" '
                f'y="{y + row_h * 0.15:.1f}" width="{f.x(b) - f.x(a):.2f}" '
                f'height="{row_h * 0.7:.1f}" fill="{LEG_COLOURS[leg]}"/>'
            )
    fmt = "{:.2f}" if window_s < 1.5 else "{:.1f}"
    out += _x_ticks(f, _time_ticks(t0, t1), fmt)
    out.append(_time_axis_label(f))
    out.append(f"<!-- {n_bars} bars --></svg>")
    return "\n".join(out)


# Drawn at most this many Delta31 points: the whole run is kept (`Simulation.d31_events`), but a
# 10-minute run has ~6000 touchdowns and the panel is redrawn 5 times a second for every browser.
MAX_DRAWN = 1200


def d31_svg(
    events: CoreEvents,
    t_now: float,
    window_s: float | None,
    gait: str,
    marks: Sequence[Mark] = (),
    job: tuple[str, Sequence[tuple[float, float]]] | None = None,
) -> str:
    """Delta31 at each leg-1 touchdown, (time_s, Delta31) as `Simulation.d31_events` has them,
    over the last `window_s` (None: the whole run), with the two gaits' lines; beyond MAX_DRAWN
    points every k-th is drawn (the title says so)."""
    whole = window_s is None
    span = max(t_now, 1.0) if window_s is None else window_s
    t0, t1 = time_window(t_now, span)
    f = Frame(t0, t1, 0.0, TWO_PI)
    shown = [(t, d) for t, d in events if t0 <= t <= t1 and math.isfinite(d)]
    k = max(1, math.ceil(len(shown) / MAX_DRAWN))
    if k > 1:
        shown = shown[::k]
    what = "whole run" if whole else f"last {span:g} s"
    thin = f", 1 in {k} drawn" if k > 1 else ""
    out = _open(
        "d31",
        f"Δ31 over time ({what}{thin}) — gait: {gait}",
        gait=gait,
        n_events=str(len(events)),
        t0=f"{t0:.3f}",
    )
    out += _y_angle_axis(f) + _reference_lines(f)
    pts = [(f.x(t), f.y(d)) for t, d in shown]
    # Delta31 is an angle: a step across 0 = 2 pi is not a swing through pi, so the line breaks
    segments: list[list[tuple[float, float]]] = []
    for i, p in enumerate(pts):
        if i == 0 or abs(shown[i][1] - shown[i - 1][1]) > math.pi:
            segments.append([])
        segments[-1].append(p)
    for seg in segments:
        if len(seg) >= 2:
            path = " ".join(f"{x:.1f},{y:.1f}" for x, y in seg)
            out.append(f'<polyline points="{path}" fill="none" stroke="#444" stroke-width="0.6"/>')
    if job is not None:  # a finished job's run, on the same time axis (both start at 0)
        name, series = job
        xy = [(f.x(t), f.y(d)) for t, d in series if t0 <= t <= t1 and math.isfinite(d)]
        out.append(dots(xy[-MAX_DRAWN:], 1.2, JOB_COLOUR, 0.8, "job"))
        out.append(
            f'<text class="job" x="{LEFT + 3}" y="{f.bottom - 4}" {FONT} fill="{JOB_COLOUR}">'
            f"● job {html.escape(name)}</text>"
        )
    out.append(dots(pts, 1.6 if len(pts) < 300 else 1.0, "#222"))
    out += _marks(f, [m for m in marks if t0 <= m.time_s <= t1])
    fmt = "{:.0f}" if span >= 4 else "{:.1f}"
    out += _x_ticks(f, _time_ticks(t0, t1), fmt)
    out.append(_time_axis_label(f))
    out.append("</svg>")
    return "\n".join(out)


MARK_COLOUR = "#9467bd"
JOB_COLOUR = "#e377c2"  # a finished job's Delta31 beside the live walk's


MARK_ROWS = 3  # label heights in turn
CHAR_W = 5.0  # px per character of a 9 px sans-serif label (an upper estimate for layout)


def _marks(f: Frame, marks: Sequence[Mark]) -> list[str]:
    """A thin vertical line where the conditions changed, with what changed beside it.

    Each label takes the first of three rows where it does not print over the previous label
    there (right of its line, or left of it at the plot's right edge); where none is free (a
    short ramp's phases on a long history) the line keeps its words as a tooltip and in
    `data-label`, and the last label printed counts the marks it stands for ("+2").
    """
    out: list[str] = []
    row_end = [-math.inf] * MARK_ROWS
    last_text: int | None = None  # index in `out` of the latest label printed
    extra = 0
    for m in marks:
        x = f.x(m.time_s)
        label = html.escape(m.label)
        out.append(
            f'<line class="mark" data-label="{label}" x1="{x:.1f}" y1="{TOP}" x2="{x:.1f}" '
            f'y2="{f.bottom}" stroke="{MARK_COLOUR}" stroke-width="0.6" stroke-dasharray="2 2">'
            f"<title>{label}</title></line>"
        )
        width = CHAR_W * len(m.label)
        left = x + 2 if x + 2 + width <= f.right else x - 2 - width
        row = next((r for r in range(MARK_ROWS) if left >= row_end[r]), None)
        if row is None:
            extra += 1
            continue
        if last_text is not None and extra:
            out[last_text] = out[last_text].replace("</text>", f" +{extra}</text>")
        extra = 0
        row_end[row] = left + width + 4
        anchor = "start" if left > x else "end"
        tx = x + 2 if anchor == "start" else x - 2
        out.append(
            f'<text class="mark" x="{tx:.1f}" y="{TOP + 9 + 9 * row}" text-anchor="{anchor}" '
            f'{FONT} fill="{MARK_COLOUR}">{label}</text>'
        )
        last_text = len(out) - 1
    if last_text is not None and extra:
        out[last_text] = out[last_text].replace("</text>", f" +{extra}</text>")
    return out


# The finder's states, coloured by gait: tripod orange, metachronal green, other grey
GAIT_COLOURS = {"tripod": "#ff7f0e", "metachronal": "#2ca02c", "other": "#7f7f7f"}
# this session's ramp: its path, drawn as it goes, one colour per direction (holds grey)
RAMP_COLOURS = {"down": "#8c564b", "up": "#9467bd", "hold": "#999999"}
LEGEND_H = 48.0  # up to four legend rows under the ticks (a long row wraps: `_legend`)
BIF_H = H + LEGEND_H


def _legend(f: Frame, rows: Sequence[Sequence[tuple[str, str]]]) -> list[str]:
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


def _marker(kind: str, x: float, y: float, colour: str) -> str:
    if kind == "stable":
        return (
            f'<circle class="stable" cx="{x:.1f}" cy="{y:.1f}" r="2.4" fill="{colour}" '
            'stroke="#333" stroke-width="0.3"/>'
        )
    if kind == "unstable":
        return (
            f'<circle class="unstable" cx="{x:.1f}" cy="{y:.1f}" r="2.4" fill="#fff" '
            'stroke="#333" stroke-width="0.8"/>'
        )
    if kind == "one-sided":
        return (
            f'<circle class="one-sided" cx="{x:.1f}" cy="{y:.1f}" r="2.0" fill="#bbb" '
            'stroke="#555" stroke-width="0.5"/>'
        )
    if kind == "ghost":
        d = 2.2
        return (
            f'<path class="ghost" d="M{x - d:.1f},{y - d:.1f}L{x + d:.1f},{y + d:.1f}'
            f'M{x - d:.1f},{y + d:.1f}L{x + d:.1f},{y - d:.1f}" stroke="#555" '
            'stroke-width="0.8"/>'
        )
    d = 1.8  # unsettled: a small grey triangle
    return (
        f'<path class="unsettled" d="M{x:.1f},{y - d:.1f}L{x + d:.1f},{y + d:.1f}'
        f'L{x - d:.1f},{y + d:.1f}Z" fill="#aaa"/>'
    )


def bifurcation_svg(
    finder: FinderPoints | None,
    note: str,
    trail: Sequence[D31Event],
    live: tuple[float, float | None],
    beta_range: tuple[float, float],
    ramp_path: Sequence[D31Event] = (),
) -> str:
    """The finder's states over beta (stable filled by gait, unstable open, one-sided grey,
    ghosts x, unsettled finals grey triangles), this session's trail, the path of a beta ramp
    (a line per direction, drawn as it goes) and the live point (red ring)."""
    lo, hi = beta_range
    f = Frame(lo, hi, 0.0, TWO_PI, h=BIF_H, legend_h=LEGEND_H)
    pts = finder or FinderPoints()
    out = _open(
        "bifurcation",
        "Bifurcation: Δ31 vs β (finder's states; this run)",
        h=BIF_H,
        legend_h=LEGEND_H,
        n_cached=str(len(pts)),
    )
    out += _y_angle_axis(f) + _reference_lines(f)
    for b, d in pts.unsettled:
        if lo <= b <= hi:
            out.append(_marker("unsettled", f.x(b), f.y(d), ""))
    for b, d in pts.ghosts:
        if lo <= b <= hi:
            out.append(_marker("ghost", f.x(b), f.y(d), ""))
    for b, d in pts.unstable:
        if lo <= b <= hi:
            out.append(_marker("unstable", f.x(b), f.y(d), ""))
    for b, d in pts.one_sided:
        if lo <= b <= hi:
            out.append(_marker("one-sided", f.x(b), f.y(d), ""))
    for b, d, gait in pts.stable:
        if lo <= b <= hi:
            colour = GAIT_COLOURS.get(gait, GAIT_COLOURS["other"])
            out.append(_marker("stable", f.x(b), f.y(d), colour))
    trail_xy = [(f.x(e.at.beta), f.y(e.d31)) for e in trail if lo <= e.at.beta <= hi]
    out.append(dots(trail_xy, 1.0, "#000", 0.35, "trail"))
    ramp = _ramp_lines(f, ramp_path, lo, hi)
    out += ramp
    beta, d31 = live
    if d31 is not None:
        out.append(
            f'<circle class="live" cx="{f.x(min(hi, max(lo, beta))):.1f}" cy="{f.y(d31):.1f}" '
            'r="3.5" fill="none" stroke="#e00" stroke-width="1.5"/>'
        )
    if note:
        out.append(_note(f, note))
    ticks = [0.55, 0.60, 0.65, 0.70, 0.75, 0.80]
    out += _x_ticks(f, [t for t in ticks if lo <= t <= hi], "{:.2f}")
    row2 = [("◯ unstable", "#333"), ("● one-sided", "#999"), ("× ghost", "#555"),
            ("▲ not settled", "#999")]  # fmt: skip
    row2 += [("◯ now", "#e00"), ("· this run", "#666")]
    rows = [[(f"● {g}", c) for g, c in GAIT_COLOURS.items()], row2]
    if ramp:
        rows.append([(f"— ramp β {d}", RAMP_COLOURS[d]) for d in ("down", "up")])
    out += _legend(f, rows)
    out.append("</svg>")
    return "\n".join(out)


def _note(f: Frame, note: str, width: int = 52) -> str:
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


def _ramp_lines(
    f: Frame, path: Sequence[D31Event], lo: float, hi: float, param: str = "beta"
) -> list[str]:
    """The ramp's (parameter, Delta31) path: one polyline per stretch of one direction, broken
    where Delta31 wraps across 0 = 2 pi (a wrap is not a swing through pi)."""
    out: list[str] = []
    segments: list[tuple[str, list[D31Event]]] = []

    def at(e: D31Event) -> float:
        return float(getattr(e.at, param))

    for i, e in enumerate(path):
        if not e.at.ramp or not lo <= at(e) <= hi:
            continue
        prev = path[i - 1] if i > 0 else None
        if (
            not segments
            or prev is None
            or segments[-1][0] != e.at.ramp
            or segments[-1][1][-1] is not prev
            or abs(e.d31 - prev.d31) > math.pi
        ):
            segments.append((e.at.ramp, []))
        segments[-1][1].append(e)
    for direction, seg in segments:
        colour = RAMP_COLOURS.get(direction, "#444")
        pts = " ".join(f"{f.x(at(e)):.1f},{f.y(e.d31):.1f}" for e in seg)
        if len(seg) >= 2:
            out.append(
                f'<polyline class="ramp" data-direction="{html.escape(direction)}" '
                f'points="{pts}" fill="none" stroke="{colour}" stroke-width="1.6"/>'
            )
        else:
            e = seg[0]
            out.append(
                f'<circle class="ramp" cx="{f.x(at(e)):.1f}" cy="{f.y(e.d31):.1f}" r="1" '
                f'fill="{colour}"/>'
            )
    return out


def ramp_path_svg(
    path: Sequence[D31Event], param: str, axis_label: str, value_range: tuple[float, float]
) -> str:
    """Delta31 against the ramped parameter during the latest ramp (Fig. 6a's own axes for a
    beta ramp; the same for body mass or slope), a line per direction as it goes."""
    lo, hi = value_range
    f = Frame(lo, hi, 0.0, TWO_PI, h=H + 11.0, legend_h=11.0)
    out = _open(
        "ramp-path",
        f"Ramp: Δ31 vs {axis_label}",
        h=H + 11.0,
        legend_h=11.0,
        param=param,
        n_events=str(len(path)),
    )
    out += _y_angle_axis(f) + _reference_lines(f)
    out += _ramp_lines(f, path, lo, hi, param)
    span = hi - lo
    step = next(s for s in (0.01, 0.02, 0.05, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0) if span / s <= 6)
    ticks = [step * k for k in range(math.ceil(lo / step), math.floor(hi / step) + 1)]
    out += _x_ticks(f, ticks, "{:.2f}" if step < 0.1 else "{:g}")
    out += _legend(f, [[(f"— {d}", RAMP_COLOURS[d]) for d in ("down", "up")]])
    out.append("</svg>")
    return "\n".join(out)


# The atlas's regions (`surface_atlas.region`): both gaits purple, one gait its colour
REGION_COLOURS = {
    "both": "#9467bd",
    "tripod only": GAIT_COLOURS["tripod"],
    "metachronal only": GAIT_COLOURS["metachronal"],
    "other states": "#c7c7c7",
    "none": "#f4f4f4",
}


def _edges(centres: Sequence[float]) -> list[float]:
    """Cell edges around sorted grid values: halfway between neighbours, half a step outside."""
    c = list(centres)
    if len(c) == 1:
        return [c[0] - 0.5, c[0] + 0.5]
    mids = [(a + b) / 2 for a, b in itertools.pairwise(c)]
    return [c[0] - (mids[0] - c[0]), *mids, c[-1] + (c[-1] - mids[-1])]


def atlas_svg(
    atlas: SurfaceAtlas | None,
    note: str,
    axis: str,
    axis_label: str,
    live: tuple[float, float],
    beta_range: tuple[float, float],
) -> str:
    """The gait atlas as a grid of cells coloured by region (beta across, mass or slope up),
    with the live (beta, value) point as a red ring; `note` when there is no atlas."""
    title = f"Atlas: {axis_label} vs β"
    if atlas is None or not atlas.betas or not atlas.values:
        lo, hi = beta_range
        f = Frame(lo, hi, 0.0, 1.0, h=BIF_H, legend_h=LEGEND_H)
        out = _open("atlas", title, h=BIF_H, legend_h=LEGEND_H, axis=axis, n_cells="0")
        out.append(_note(f, note or f"no atlas over {axis}"))
        out.append("</svg>")
        return "\n".join(out)
    order_b = sorted(range(len(atlas.betas)), key=lambda j: atlas.betas[j])
    order_v = sorted(range(len(atlas.values)), key=lambda i: atlas.values[i])
    be = _edges([atlas.betas[j] for j in order_b])
    ve = _edges([atlas.values[i] for i in order_v])
    f = Frame(be[0], be[-1], ve[0], ve[-1], h=BIF_H, legend_h=LEGEND_H)
    out = _open(
        "atlas",
        title,
        h=BIF_H,
        legend_h=LEGEND_H,
        axis=axis,
        n_cells=str(len(atlas.betas) * len(atlas.values)),
    )
    nb = len(atlas.betas)
    for vi, i in enumerate(order_v):
        for bj, j in enumerate(order_b):
            region = atlas.regions[i][j]
            # faint where a zero or near-zero band in the window stayed unresolved: the region
            # may hide a gait (the tripod's narrow pair, most often)
            unresolved = atlas.points[i * nb + j].unresolved > 0
            x0, x1 = f.x(be[bj]), f.x(be[bj + 1])
            y0, y1 = f.y(ve[vi + 1]), f.y(ve[vi])
            out.append(
                f'<rect class="cell" data-region="{html.escape(region)}" '
                f'data-unresolved="{str(unresolved).lower()}" x="{x0:.1f}" '
                f'y="{y0:.1f}" width="{x1 - x0:.1f}" height="{y1 - y0:.1f}" '
                f'fill="{REGION_COLOURS.get(region, "#fff")}" '
                f'fill-opacity="{0.5 if unresolved else 1}" stroke="#fff" stroke-width="0.5">'
                f"<title>β {atlas.betas[j]:g}, {html.escape(axis_label)} {atlas.values[i]:g}: "
                f"{html.escape(region)}{' (unresolved zeros here)' if unresolved else ''}"
                "</title></rect>"
            )
    beta, value = live
    inside = be[0] <= beta <= be[-1] and ve[0] <= value <= ve[-1]
    cx = f.x(min(be[-1], max(be[0], beta)))
    cy = f.y(min(ve[-1], max(ve[0], value)))
    out.append(
        f'<circle class="live" data-inside="{str(inside).lower()}" cx="{cx:.1f}" cy="{cy:.1f}" '
        'r="3.5" fill="none" stroke="#e00" stroke-width="1.5"/>'
    )
    step = max(1, math.ceil(nb / 6))
    out += _x_ticks(f, [atlas.betas[j] for j in order_b][::step], "{:.3g}")
    nv = len(atlas.values)
    vstep = max(1, math.ceil(nv / 6))
    for i in order_v[::vstep]:
        v = atlas.values[i]
        out.append(
            f'<text x="{LEFT - 3}" y="{f.y(v) + 3:.1f}" {FONT} text-anchor="end">{v:g}</text>'
        )
    regions = list(REGION_COLOURS.items())
    rows = [
        [(f"■ {r}", c if r != "none" else "#999") for r, c in regions[:3]],
        [(f"■ {r}", c if r != "none" else "#999") for r, c in regions[3:]]
        + [("faint: unresolved", "#999"), ("◯ now", "#e00")],
    ]
    out += _legend(f, rows)
    out.append("</svg>")
    return "\n".join(out)


RM = 190  # the return map's square viewBox (drawn at RM / W of the panel's width)
RM_TITLE_H = 10.0  # room under the ticks for the x axis' title
RECENCY_SHADES = 6  # the return map's age groups, each one path of one opacity


def return_map_svg(pairs: Sequence[tuple[float, float]], lag: int = 4) -> str:
    """Delta31(n) -> Delta31(n + lag) of the current run: a fixed point sits on the diagonal;
    newer pairs are darker."""
    f = Frame(0.0, TWO_PI, 0.0, TWO_PI, w=RM, h=RM, legend_h=RM_TITLE_H)
    out = _open(
        "return-map",
        f"Return map: Δ31(n) → Δ31(n+{lag})",
        w=RM,
        h=RM,
        legend_h=RM_TITLE_H,
        n_pairs=str(len(pairs)),
    )
    out += _y_angle_axis(f)
    mid_x, mid_y = (f.x(0.0) + f.x(TWO_PI)) / 2, (f.y(0.0) + f.y(TWO_PI)) / 2
    out.append(
        f'<text class="axis-title" x="{mid_x:.1f}" y="{f.bottom + 21}" {FONT} fill="#666" '
        f'text-anchor="middle">Δ31(n) (rad)</text>'
    )
    out.append(
        f'<text class="axis-title" x="8" y="{mid_y:.1f}" {FONT} fill="#666" text-anchor="middle" '
        f'transform="rotate(-90 8 {mid_y:.1f})">Δ31(n+{lag}) (rad)</text>'
    )
    out.append(
        f'<line x1="{f.x(0):.1f}" y1="{f.y(0):.1f}" x2="{f.x(TWO_PI):.1f}" '
        f'y2="{f.y(TWO_PI):.1f}" stroke="#999" stroke-width="0.6" stroke-dasharray="3 2"/>'
    )
    shown = [(f.x(x), f.y(y)) for x, y in list(pairs)[-MAX_DRAWN:]]
    # newer darker: RECENCY_SHADES groups of equal size, oldest faintest
    for k, group in enumerate(np.array_split(np.arange(len(shown)), RECENCY_SHADES)):
        if len(group):
            pts = [shown[i] for i in group]
            out.append(dots(pts, 1.2, "#222", 0.15 + 0.85 * (k + 1) / RECENCY_SHADES))
    for v, label in ((0.0, "0"), (TWO_PI / 3, "2π/3"), (math.pi, "π"), (TWO_PI, "2π")):
        out.append(
            f'<text x="{f.x(v):.1f}" y="{f.bottom + 11}" {FONT} text-anchor="middle">{label}</text>'
        )
    out.append("</svg>")
    return "\n".join(out)

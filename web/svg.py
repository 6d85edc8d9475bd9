"""The panels' diagrams as small inline SVG strings (viser shows them with `gui.add_html`).

SVG rather than a plotting widget because the footfall diagram is bars, not lines: each stance
interval is one <rect>, coloured per leg pair, and nothing has to be encoded as gaps in a series.
The functions are pure (numbers in, markup out), so a test can check what a browser will draw.
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence
from dataclasses import dataclass

from sim_core.contract import LEG_NAMES
from web.footfall import D31Event

LEG_ORDER = LEG_NAMES  # the paper's legs 1-6, rows top to bottom
# Fig. 4's colouring by leg pair: fore (legs 1-2) red, middle (3-4) blue, hind (5-6) green;
# right legs in the full colour, left legs in a light tint of it, so that both the pair and the
# side read at a glance: a tripod is a checkerboard (R1 L2 R3 against L1 R2 L3), a metachronal
# wave a staircase running from hind to fore on each side.
PAIR_COLOURS = ("#d62728", "#1f77b4", "#2ca02c")
PAIR_NAMES = ("fore", "middle", "hind")
LEFT_TINTS = ("#f1a3a4", "#9cc7e8", "#9fdc9f")
LEG_COLOURS = tuple(PAIR_COLOURS[i // 2] if i % 2 == 0 else LEFT_TINTS[i // 2] for i in range(6))
TWO_PI = 2.0 * math.pi

W, H = 300, 150  # viewBox; the panel scales it to its width
LEFT, RIGHT, TOP, BOTTOM = 34, 14, 16, 20
FONT = 'font-family="sans-serif" font-size="9"'


@dataclass(frozen=True)
class Frame:
    """Maps data coordinates into the plot area of the viewBox."""

    x0: float
    x1: float
    y0: float
    y1: float

    def x(self, v: float) -> float:
        span = self.x1 - self.x0 or 1.0
        return LEFT + (v - self.x0) / span * (W - LEFT - RIGHT)

    def y(self, v: float) -> float:
        span = self.y1 - self.y0 or 1.0
        return H - BOTTOM - (v - self.y0) / span * (H - TOP - BOTTOM)


def _open(kind: str, title: str, **attrs: str) -> list[str]:
    extra = "".join(f' data-{k.replace("_", "-")}="{html.escape(v)}"' for k, v in attrs.items())
    return [
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {W} {H}" width="100%" '
        f'data-plot="{kind}"{extra} style="background:#fff">',
        f'<text x="{LEFT}" y="11" {FONT} font-weight="bold">{html.escape(title)}</text>',
        f'<rect x="{LEFT}" y="{TOP}" width="{W - LEFT - RIGHT}" height="{H - TOP - BOTTOM}" '
        'fill="none" stroke="#999" stroke-width="0.5"/>',
    ]


def time_window(t_now: float, window_s: float) -> tuple[float, float]:
    """The scrolling plots' time axis: [0, window] until the run is that old, then the last
    `window_s` (never a negative time: the run starts at 0)."""
    t1 = max(t_now, window_s)
    return t1 - window_s, t1


def _time_axis_label() -> str:
    """The unit of the time ticks, in the free corner left of the axis."""
    return (
        f'<text x="{LEFT - 3}" y="{H - BOTTOM + 11}" {FONT} text-anchor="end" '
        'fill="#666">t (s)</text>'
    )


def _x_ticks(f: Frame, ticks: Sequence[float], fmt: str) -> list[str]:
    out = []
    for v in ticks:
        x = f.x(v)
        out.append(
            f'<line x1="{x:.1f}" y1="{H - BOTTOM}" x2="{x:.1f}" y2="{H - BOTTOM + 3}" '
            'stroke="#999" stroke-width="0.5"/>'
        )
        out.append(
            f'<text x="{x:.1f}" y="{H - BOTTOM + 11}" {FONT} text-anchor="middle">'
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
            f'<line x1="{LEFT}" y1="{y:.1f}" x2="{W - RIGHT}" y2="{y:.1f}" stroke="{colour}" '
            'stroke-width="0.7" stroke-dasharray="4 3"/>'
        )
        out.append(
            f'<text x="{W - RIGHT - 2}" y="{y - 2:.1f}" {FONT} fill="{colour}" '
            f'text-anchor="end">{name}</text>'
        )
    return out


def _time_ticks(t0: float, t1: float) -> list[float]:
    span = t1 - t0
    step = next((s for s in (0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0) if span / s <= 6), 10.0)
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
    out.append(_time_axis_label())
    out.append(f"<!-- {n_bars} bars --></svg>")
    return "\n".join(out)


def d31_svg(events: Sequence[D31Event], t_now: float, window_s: float, gait: str) -> str:
    """Delta31 at each leg-1 touchdown over the last `window_s`, with the two gaits' lines."""
    t0, t1 = time_window(t_now, window_s)
    f = Frame(t0, t1, 0.0, TWO_PI)
    out = _open("d31", f"Δ31 over time — gait: {gait}", gait=gait, n_events=str(len(events)))
    out += _y_angle_axis(f) + _reference_lines(f)
    shown = [e for e in events if t0 <= e.time_s <= t1]
    pts = [(f.x(e.time_s), f.y(e.d31)) for e in shown]
    # Delta31 is an angle: a step across 0 = 2 pi is not a swing through pi, so the line breaks
    segments: list[list[tuple[float, float]]] = []
    for i, p in enumerate(pts):
        if i == 0 or abs(shown[i].d31 - shown[i - 1].d31) > math.pi:
            segments.append([])
        segments[-1].append(p)
    for seg in segments:
        if len(seg) >= 2:
            path = " ".join(f"{x:.1f},{y:.1f}" for x, y in seg)
            out.append(f'<polyline points="{path}" fill="none" stroke="#444" stroke-width="0.6"/>')
    for x, y in pts:
        out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="1.6" fill="#222"/>')
    fmt = "{:.0f}" if window_s >= 4 else "{:.1f}"
    out += _x_ticks(f, _time_ticks(t0, t1), fmt)
    out.append(_time_axis_label())
    out.append("</svg>")
    return "\n".join(out)


# series names in cached results -> colours: the two sweep directions of a hysteresis loop
_SERIES_COLOURS = {"down": "#ff7f0e", "up": "#9467bd"}
# this session's ramp: its path, drawn as it goes, in darker shades of the same two colours
_RAMP_COLOURS = {"down": "#c45a00", "up": "#5b2d8c"}
_FALLBACK_COLOURS = ("#7f7f7f", "#17becf", "#bcbd22", "#8c564b")


def bifurcation_svg(
    cached: dict[str, list[tuple[float, float]]] | None,
    note: str,
    trail: Sequence[D31Event],
    live: tuple[float, float | None],
    beta_range: tuple[float, float],
    ramp_path: Sequence[D31Event] = (),
) -> str:
    """Cached (beta, Delta31) points per series, this session's trail, the path of the beta
    ramp (a line per direction, drawn as the ramp goes) and the live point."""
    lo, hi = beta_range
    f = Frame(lo, hi, 0.0, TWO_PI)
    out = _open("bifurcation", "Bifurcation: Δ31 vs β", n_cached=str(_count(cached)))
    out += _y_angle_axis(f) + _reference_lines(f)
    legend_x = LEFT + 4
    for k, (name, pts) in enumerate((cached or {}).items()):
        colour = _SERIES_COLOURS.get(name, _FALLBACK_COLOURS[k % len(_FALLBACK_COLOURS)])
        for b, d in pts:
            if lo <= b <= hi:
                out.append(
                    f'<circle cx="{f.x(b):.1f}" cy="{f.y(d):.1f}" r="1.5" fill="{colour}" '
                    'fill-opacity="0.7"/>'
                )
        out.append(
            f'<text x="{legend_x}" y="{TOP + 10 + 10 * k}" {FONT} fill="{colour}">'
            f"● {html.escape(name)}</text>"
        )
    for e in trail:
        if lo <= e.beta <= hi:
            out.append(
                f'<circle cx="{f.x(e.beta):.1f}" cy="{f.y(e.d31):.1f}" r="1" fill="#000" '
                'fill-opacity="0.35"/>'
            )
    out += _ramp_lines(f, ramp_path, lo, hi)
    beta, d31 = live
    if d31 is not None:
        out.append(
            f'<circle class="live" cx="{f.x(min(hi, max(lo, beta))):.1f}" cy="{f.y(d31):.1f}" '
            'r="3.5" fill="none" stroke="#e00" stroke-width="1.5"/>'
        )
    if note:
        out.append(
            f'<text x="{(LEFT + W - RIGHT) / 2:.0f}" y="{H - BOTTOM - 6}" {FONT} fill="#a00" '
            f'text-anchor="middle">{html.escape(note)}</text>'
        )
    ticks = [0.55, 0.60, 0.65, 0.70, 0.75, 0.80]
    out += _x_ticks(f, [t for t in ticks if lo <= t <= hi], "{:.2f}")
    out.append("</svg>")
    return "\n".join(out)


def _ramp_lines(f: Frame, path: Sequence[D31Event], lo: float, hi: float) -> list[str]:
    """The ramp's (beta, Delta31) path: one polyline per stretch of one direction, broken where
    Delta31 wraps across 0 = 2 pi (a wrap is not a swing through pi)."""
    out: list[str] = []
    segments: list[tuple[str, list[D31Event]]] = []
    for i, e in enumerate(path):
        if not e.ramp or not lo <= e.beta <= hi:
            continue
        prev = path[i - 1] if i > 0 else None
        if (
            not segments
            or prev is None
            or segments[-1][0] != e.ramp
            or segments[-1][1][-1] is not prev
            or abs(e.d31 - prev.d31) > math.pi
        ):
            segments.append((e.ramp, []))
        segments[-1][1].append(e)
    for direction, seg in segments:
        colour = _RAMP_COLOURS.get(direction, "#444")
        pts = " ".join(f"{f.x(e.beta):.1f},{f.y(e.d31):.1f}" for e in seg)
        if len(seg) >= 2:
            out.append(
                f'<polyline class="ramp" data-direction="{html.escape(direction)}" '
                f'points="{pts}" fill="none" stroke="{colour}" stroke-width="1.6"/>'
            )
        else:
            e = seg[0]
            out.append(
                f'<circle class="ramp" cx="{f.x(e.beta):.1f}" cy="{f.y(e.d31):.1f}" r="1" '
                f'fill="{colour}"/>'
            )
    if segments:
        for k, direction in enumerate(("down", "up")):
            out.append(
                f'<text x="{W - RIGHT - 2}" y="{TOP + 30 + 10 * k}" {FONT} text-anchor="end" '
                f'fill="{_RAMP_COLOURS[direction]}">ramp β {direction}</text>'
            )
    return out


def _count(cached: dict[str, list[tuple[float, float]]] | None) -> int:
    return sum(len(v) for v in (cached or {}).values())

"""Every SVG panel the viewer draws stays legible: no two words print over each other.

Each panel is drawn at the default width (the 300-wide viewBox the page scales) from realistic
inputs: the result files the viewer reads (docs/figures), a long run with many marks, long
labels and notes, ramps of each parameter. The SVG is parsed and each <text> (each <tspan> line
of a note) gets a box estimated from its x, y, font-size, text-anchor and character count with
a conservative per-character width (`text_boxes`); no two boxes may overlap, and none may leave
the viewBox (a clipped word is not legible either).

The width per character is an upper bound measured, not the layout's own constant: in the
headless Chromium the browser tests use (DejaVu Sans for "sans-serif"), a short label reached
0.69 em a character (a lone "π"), a text of 20 characters or more 0.51 em (bold titles 0.54),
over every text these panels draw; so a label counts 0.7 em a character, a longer text 0.62 em,
and bold 1.1 times that.
"""

from __future__ import annotations

import itertools
import math
import re
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from sim_core.contract import DriftSurface, EventConditions, FinderOutput, SurfaceAtlas
from web.atlas_svg import atlas_svg
from web.bifurcation import finder_points, load_validated
from web.bifurcation_svg import bifurcation_svg, ramp_path_svg
from web.d31_svg import d31_svg
from web.footfall_svg import footfall_svg
from web.record import D31Event, Mark
from web.surface_svg import surface_svg

FIGURES = Path(__file__).resolve().parents[2] / "docs" / "figures"
BETAS = (0.55, 0.80)  # the viewer's beta slider: the bifurcation and surface panels' x axis
NS = "{http://www.w3.org/2000/svg}"

SHORT_EM, LONG_EM, LONG = 0.7, 0.62, 20  # width per character, in em (the module's docstring)
BOLD = 1.1  # a bold title is this much wider
ASCENT_EM, DESCENT_EM = 0.76, 0.2  # above and below the baseline


@dataclass(frozen=True)
class Box:
    """Where a line of text prints, in viewBox units, and what it says."""

    x0: float
    y0: float
    x1: float
    y1: float
    text: str

    def overlaps(self, other: Box) -> bool:
        """True when the two boxes share an area (touching edges do not count)."""
        eps = 0.01
        return (
            self.x0 < other.x1 - eps
            and other.x0 < self.x1 - eps
            and self.y0 < other.y1 - eps
            and other.y0 < self.y1 - eps
        )


def text_box(x: float, y: float, text: str, size: float, anchor: str, bold: bool) -> Box:
    """The box a line of `text` at (x, y) is drawn in: the estimate every check here uses."""
    em = SHORT_EM if len(text) < LONG else LONG_EM
    width = len(text) * em * size * (BOLD if bold else 1.0)
    x0 = {"start": x, "middle": x - width / 2, "end": x - width}[anchor]
    return Box(x0, y - ASCENT_EM * size, x0 + width, y + DESCENT_EM * size, text)


def _lines(el: ET.Element) -> Iterator[tuple[ET.Element, str]]:
    """The element's lines: its <tspan>s where it has them, else its own text (a <title> child
    is a tooltip, not drawn)."""
    spans = el.findall(f"{NS}tspan")
    if spans:
        yield from ((s, s.text or "") for s in spans)
    else:
        yield el, (el.text or "") + "".join(c.tail or "" for c in el)


def text_boxes(svg: str) -> list[Box]:
    """Every drawn line of text in `svg`, with its estimated box."""
    root = ET.fromstring(svg)
    out = []
    for el in root.iter(f"{NS}text"):
        size = float(el.get("font-size", "9"))
        anchor = el.get("text-anchor", "start")
        bold = el.get("font-weight") == "bold"
        for line, text in _lines(el):
            if text.strip():
                x = float(line.get("x", el.get("x", "0")))
                y = float(line.get("y", el.get("y", "0")))
                out.append(text_box(x, y, text.strip(), size, anchor, bold))
    return out


def clashes(svg: str) -> list[str]:
    """Pairs of texts that overlap, and texts outside the viewBox, in words."""
    boxes = text_boxes(svg)
    _, _, w, h = (float(v) for v in ET.fromstring(svg).get("viewBox", "").split())
    out = [
        f"{a.text!r} over {b.text!r}" for a, b in itertools.combinations(boxes, 2) if a.overlaps(b)
    ]
    out += [
        f"{b.text!r} leaves the viewBox"
        for b in boxes
        if b.x0 < 0 or b.y0 < 0 or b.x1 > w or b.y1 > h
    ]
    return out


# ----- realistic inputs, the ones the viewer meets -----


def _bars(t_now: float, window_s: float, beta: float = 0.62) -> list[list[tuple[float, float]]]:
    """A tripod's stance bars (period 0.1 s / (1 - beta)-ish) over the window."""
    period = 0.36
    out = []
    for leg in range(6):
        offset = period / 2 * ((leg + leg // 2) % 2)
        start = math.floor((t_now - window_s - 1) / period) * period + offset
        bars = []
        while start < t_now:
            bars.append((start, min(t_now, start + beta * period)))
            start += period
        out.append(bars)
    return out


def _events(t_now: float, dt: float = 0.36) -> list[tuple[float, float]]:
    n = int(t_now / dt)
    return [(k * dt, 2.0 + 0.9 * (1 - math.exp(-k * dt / 20))) for k in range(1, n + 1)]


MARKS = [
    Mark(2.3, "β 0.620"),
    Mark(5.0, "mass 4.50 g"),
    Mark(5.4, "β 0.645, mass 6.00 g, slope 12.5°"),  # a long label next to another
    Mark(8.0, "ramp β hold", False),
    Mark(8.3, "ramp β up", False),
    Mark(12.0, "ramp over", False),
    *(Mark(50.0 + 0.1 * k, f"ramp mass phase {k}", False) for k in range(6)),  # crowded
    Mark(79.0, "slope 20.0°"),  # at the right edge: its label turns left
]


def _ramp(param: str, start: float, turn: float, n: int = 300) -> list[D31Event]:
    """A ramp's path: down (or up) to the turn and back, Delta31 moving between the branches."""
    out = []
    for k in range(n):
        half = k < n // 2
        s = k / (n // 2) if half else (k - n // 2) / (n - n // 2)
        value = start + (turn - start) * (s if half else 1 - s)
        direction = (
            ("down" if turn < start else "up") if half else ("up" if turn < start else "down")
        )
        d31 = 1.9 + 1.0 * s if half else 2.9 - 1.0 * s
        at = EventConditions(
            value if param == "beta" else 0.66,
            value if param == "body_mass_g" else 3.0,
            value if param == "slope_deg" else 0.0,
            ramp=direction,
            ramp_param=param,
        )
        out.append(D31Event(0.36 * k, d31, at))
    return out


LONG_NOTE = (
    "no drift surface for the paper's ground at 6.00 g on a 12.5° slope: "
    "/home/someone/results/surface_penalty_mass6_slope12.json is absent; run "
    "`insect-gait reproduce --figures surface` or submit a surface job"
)


def _load(name: str, model: type) -> object:
    value, note = load_validated(FIGURES / name, model, name)
    assert value is not None, note
    return value


def panels() -> Iterator[tuple[str, str]]:
    """(name, SVG) of every panel the viewer draws, in the situations that crowd them."""
    for t_now, window in ((0.3, 0.5), (12.37, 0.5), (12.37, 3.0), (617.2, 3.0)):
        yield f"footfall t={t_now} w={window}", footfall_svg(_bars(t_now, window), t_now, window)
    ev = _events(80.0)
    yield "d31 start", d31_svg(_events(1.0), 1.0, 30.0, "metachronal")
    yield "d31 whole run, marks", d31_svg(ev, 80.0, None, "other", MARKS)
    yield (
        "d31 last 30 s, job",
        d31_svg(
            [e for e in ev if e[0] >= 50.0], 80.0, 30.0, "tripod", MARKS, ("3f9a1c2e", ev[::2])
        ),
    )
    yield "d31 long run", d31_svg(_events(617.2), 617.2, None, "tripod")
    surface = _load("surface.json", DriftSurface)
    assert isinstance(surface, DriftSurface)
    yield "surface", surface_svg(surface, "", (0.66, 2.3), BETAS)
    yield "surface outside", surface_svg(surface, "", (0.8, 4.5), BETAS)
    yield "surface absent", surface_svg(None, LONG_NOTE, (0.66, 2.3), BETAS)
    finder = _load("bifurcation.json", FinderOutput)
    assert isinstance(finder, FinderOutput)
    pts = finder_points(finder)
    beta_ramp = _ramp("beta", 0.70, 0.62)
    trail = beta_ramp[:200]
    yield "bifurcation", bifurcation_svg(pts, "", trail, (0.66, 2.3), BETAS)
    yield "bifurcation ramp", bifurcation_svg(pts, "", trail, (0.62, 2.9), BETAS, beta_ramp)
    yield "bifurcation absent", bifurcation_svg(None, LONG_NOTE, [], (0.66, None), BETAS)
    for axis, label, value in (("mass", "body mass (g)", 3.0), ("slope", "slope (°)", 0.0)):
        for ground in ("constraint", "penalty"):
            atlas = _load(f"surface_atlas_{axis}_{ground}.json", SurfaceAtlas)
            assert isinstance(atlas, SurfaceAtlas)
            yield f"atlas {axis} {ground}", atlas_svg(atlas, "", axis, label, (0.66, value), BETAS)
    yield "atlas absent", atlas_svg(None, LONG_NOTE, "slope", "slope (°)", (0.66, 0.0), BETAS)
    for param, label, start, turn in (
        ("beta", "β", 0.70, 0.62),
        ("body_mass_g", "body mass (g)", 3.0, 6.0),
        ("slope_deg", "slope (°)", 0.0, 20.0),
    ):
        a, b = sorted((start, turn))
        pad = 0.1 * (b - a)
        path = _ramp(param, start, turn)
        yield f"ramp {param}", ramp_path_svg(path, param, label, (a - pad, b + pad))


PANELS = dict(panels())


@pytest.mark.parametrize("name", list(PANELS))
def test_no_text_prints_over_another(name: str) -> None:
    svg = PANELS[name]
    assert len(text_boxes(svg)) >= 3  # the title and ticks at least: the parse found them
    assert not clashes(svg), f"{name}: " + "; ".join(clashes(svg))


def test_every_kind_of_panel_is_checked() -> None:
    kinds = {m[1] for svg in PANELS.values() if (m := re.search(r'data-plot="([\w-]+)"', svg))}
    assert kinds == {"footfall", "d31", "surface", "bifurcation", "atlas", "ramp-path"}


def test_the_estimate_catches_words_printed_over_each_other() -> None:
    """The check can fail: two labels a few pixels apart on one line, or one row above the
    other closer than a line, overlap; a word cut by the viewBox's edge is reported."""
    head = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 300 150">'
    same_row = f'{head}<text x="10" y="20" font-size="9">t (s)</text>' \
        '<text x="30" y="20" font-size="9" text-anchor="middle">0.00</text></svg>'  # fmt: skip
    assert clashes(same_row) == ["'t (s)' over '0.00'"]
    close_rows = f'{head}<text x="10" y="20" font-size="9">drift per cycle</text>' \
        '<text x="40" y="26" font-size="9">near zero</text></svg>'  # fmt: skip
    assert clashes(close_rows)
    apart = f'{head}<text x="10" y="20" font-size="9">drift per cycle</text>' \
        '<text x="10" y="31" font-size="9">near zero</text></svg>'  # fmt: skip
    assert clashes(apart) == []
    cut = f'{head}<text x="298" y="20" font-size="9" text-anchor="start">2π</text></svg>'
    assert clashes(cut) == ["'2π' leaves the viewBox"]

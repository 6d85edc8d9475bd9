"""The legend under a panel's x ticks, laid out before the panel is drawn.

Its own module because a legend decides the panel's height: its entries wrap onto as many
rows as the width needs, and the rows drawn after it (the drift surface's colour scale) and
the viewBox must count those rows, not the rows asked for (the surface panel's scale printed
over its legend's second row when a long first row wrapped). So the layout comes first
(`legend_lines`), the frame is made with its height (`rows_height`), then it is drawn.
"""

from __future__ import annotations

import html
from collections.abc import Sequence

from web.svg import CHAR_W, FONT, LINE, TICK_Y, TITLE_X, Frame, W

Entry = tuple[str, str]  # markup of a symbol + words, its colour
GAP = 10.0  # px between two entries on a row
LEGEND_X = TITLE_X  # the legend's lines start under the title, at the panel's left edge


def label_width(text: str) -> float:
    """The width a label of 9 px text takes at most (`CHAR_W` a character)."""
    return CHAR_W * len(html.unescape(text))


def legend_lines(rows: Sequence[Sequence[Entry]], w: float = W) -> list[list[tuple[float, Entry]]]:
    """Each row's entries left to right with their x; a row that would leave the panel wraps
    onto a line of its own."""
    lines: list[list[tuple[float, Entry]]] = []
    for row in rows:
        lines.append([])
        x = LEGEND_X
        for entry in row:
            width = label_width(entry[0])
            if x > LEGEND_X and x + width > w - 2:
                lines.append([])
                x = LEGEND_X
            lines[-1].append((x, entry))
            x += width + GAP
    return lines


def rows_height(n_rows: int) -> float:
    """The room `n_rows` lines take under the x ticks (`panel_frame`'s `below`)."""
    return LINE * n_rows


def row_y(f: Frame, row: int) -> float:
    """The baseline of line `row` under the x ticks."""
    return f.bottom + TICK_Y + LINE * (row + 1)


def legend(f: Frame, lines: Sequence[Sequence[tuple[float, Entry]]], first: int = 0) -> list[str]:
    """The laid-out lines, from line `first` under the ticks. Below the plot so it never
    covers data or the gait lines' labels."""
    out = []
    for r, line in enumerate(lines):
        y = row_y(f, first + r)
        for x, (text, colour) in line:
            out.append(f'<text x="{x:.0f}" y="{y:.0f}" {FONT} fill="{colour}">{text}</text>')
    return out

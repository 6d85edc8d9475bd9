"""The paper's numbers drawn beside ours: Fujiki et al. 2013's transition betas (Fig. 6a, Sec.
III B) as dashed verticals and its Fig. 8 stable ranges as pale bands at the branch values.

The numbers are the core's (`PAPER`, sim_core/contract/values.py, through the contract), never
retyped here, so a panel and `reproduce`'s comparison table cannot disagree about what the
paper says. One home for the marks and their legend words, so that every panel marks the
paper's numbers alike and a reader learns the look once.
"""

from __future__ import annotations

from sim_core.contract import PAPER
from web.legend_svg import Entry
from web.svg import FONT, Frame

PAPER_COLOUR = "#555"
DASH = "1.5 2"
# the paper's transitions, (beta, the ramp's direction that meets it): metachronal -> tripod
# as beta falls (speeding up), tripod -> metachronal as it rises
TRANSITIONS = ((PAPER.transition_down, "down"), (PAPER.transition_up, "up"))


def _vertical(f: Frame, beta: float, direction: str, colour: str) -> str:
    x = f.x(beta)
    return (
        f'<line class="paper" data-beta="{beta:g}" data-direction="{direction}" '
        f'x1="{x:.1f}" y1="{f.top:g}" x2="{x:.1f}" y2="{f.bottom:g}" stroke="{colour}" '
        f'stroke-width="0.9" stroke-dasharray="{DASH}"><title>paper: {direction} '
        f"transition at β {beta:g}</title></line>"
    )


def paper_transitions(
    f: Frame, colours: dict[str, str] | None = None, label: bool = False
) -> list[str]:
    """The paper's transition betas inside the frame's beta range as dashed verticals
    (coloured per direction when `colours` is given, as on the ramp panel); `label` writes
    "paper" beside them at the plot's top."""
    shown = [(b, d) for b, d in TRANSITIONS if min(f.x0, f.x1) <= b <= max(f.x0, f.x1)]
    out = [_vertical(f, b, d, (colours or {}).get(d, PAPER_COLOUR)) for b, d in shown]
    if label and shown:
        x = max(f.x(b) for b, _ in shown) + 2
        out.append(
            f'<text class="paper" x="{x:.1f}" y="{f.top + 9:g}" {FONT} '
            f'fill="{PAPER_COLOUR}">paper</text>'
        )
    return out


def transitions_entry(what: str = "paper") -> Entry:
    """The legend's words for the verticals, with the paper's betas."""
    return (
        f"┆ {what}: β {PAPER.transition_down:g} ↓ {PAPER.transition_up:g} ↑",
        PAPER_COLOUR,
    )


def paper_ranges(f: Frame, colours: dict[str, str]) -> list[str]:
    """Fig. 8's stable ranges: a pale band per gait over its range of beta, at the gait's
    branch value (Fig. 5), in the gait's colour."""
    out = []
    for gait, (lo, hi), d31 in (
        ("tripod", PAPER.tripod_stable, PAPER.branch_tripod_rad),
        ("metachronal", PAPER.metachronal_stable, PAPER.branch_metachronal_rad),
    ):
        y = f.y(d31)
        out.append(
            f'<line class="paper-range" data-gait="{gait}" x1="{f.x(lo):.1f}" y1="{y:.1f}" '
            f'x2="{f.x(hi):.1f}" y2="{y:.1f}" stroke="{colours[gait]}" stroke-opacity="0.3" '
            f'stroke-width="6"><title>paper, Fig. 8: {gait} stable for β {lo:g} to {hi:g} '
            f"(Δ31 {d31:g} rad)</title></line>"
        )
    return out


RANGES_ENTRY: Entry = ("▬ paper: Fig. 8 stable ranges", PAPER_COLOUR)

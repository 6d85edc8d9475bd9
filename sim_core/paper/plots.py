"""PNG figures for `insect-gait reproduce`, labelled like the paper's Figs. 5-9.

Each function draws from the JSON-able data of a `FigureData` (so a figure can be redrawn from
its JSON file alone) and marks what the paper states, in grey, next to ours: the branches 2.9
and 1.9 rad, the transitions at beta 0.645 and 0.67, the stable ranges, the ghosts.
Matplotlib with the Agg backend: files only, no display.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from sim_core.contract.values import METACHRONAL_BRANCH, TRIPOD_BRANCH, PaperValues
from sim_core.model.gait import TWO_PI

PAPER_STYLE: dict[str, Any] = {"color": "0.55", "lw": 0.9}
# leg colours of the paper's Fig. 4: fore red, middle blue, hind green
LEG_COLOURS = {0: "tab:red", 1: "tab:red", 2: "tab:blue", 3: "tab:blue", 4: "tab:green",
               5: "tab:green"}  # fmt: skip
LEG_ROWS = (0, 2, 4, 1, 3, 5)  # R1 R2 R3 above L1 L2 L3 (paper leg numbers 1 3 5 / 2 4 6)
D31 = "Δ31 (rad)"
LEG_STYLE = {"first": ("tab:red", "first leg"), "second": ("tab:blue", "return leg")}


def _branches(ax: Any, axis: str = "y") -> None:
    line = ax.axhline if axis == "y" else ax.axvline
    line(TRIPOD_BRANCH, ls="--", **PAPER_STYLE, label="paper: tripod 2.9 rad")
    line(METACHRONAL_BRANCH, ls=":", **PAPER_STYLE, label="paper: metachronal 1.9 rad")


def _save(fig: Any, path: Path) -> None:
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def fig5(data: dict[str, Any], path: Path) -> None:
    betas = sorted({r["beta"] for r in data["runs"]})
    fig, axes = plt.subplots(1, len(betas), figsize=(5 * len(betas), 3.6), sharey=True,
                             squeeze=False)  # fmt: skip
    for ax, beta in zip(axes[0], betas, strict=True):
        for r in (r for r in data["runs"] if r["beta"] == beta):
            if r["error"] is None:
                ax.plot(range(len(r["d31"])), r["d31"], ".-", ms=3, lw=0.5,
                        label=f"start {r['d31_init']:.2f}")  # fmt: skip
        _branches(ax)
        s = data.get("summary", {}).get(str(beta))
        hits = f": {s['hits']} of {s['runs']} runs on the paper's branch" if s else ""
        ax.set_title(f"β = {beta:.2f}{hits}")
        ax.set_xlabel("gait cycle n (leg-1 touchdowns)")
        ax.set_ylim(0, TWO_PI)
    axes[0][0].set_ylabel(D31)
    axes[0][0].legend(loc="lower right", fontsize=6, ncol=2)
    _save(fig, path)


def _sweep_axes(ax: Any, sweep: dict[str, Any], series: dict[str, Any], xlabel: str,
                paper: dict[str, float] | None = None) -> None:  # fmt: skip
    t = np.asarray(series["d31_times_s"])
    v = np.asarray(series["value"])
    d = np.asarray(series["d31"])
    turn_t = sweep["hold_s"] + sweep["ramp_s"]
    for leg, sel in (("first", t < turn_t), ("second", t >= turn_t)):
        colour, label = LEG_STYLE[leg]
        arrow = "→" if (sweep["turn"] > sweep["start"]) == (leg == "first") else "←"
        ax.plot(v[sel], d[sel], ".", ms=2.5, color=colour, label=f"{label} {arrow}")
        for tr in sweep[f"{leg}_leg"][:1]:
            ax.axvline(tr["value"], color=colour, lw=1.2, label=f"ours {tr['value']:.4g}")
    for name, x in (paper or {}).items():
        ax.axvline(x, ls="-.", **PAPER_STYLE)
        ax.text(x, 0.15, f" paper {name} {x}", rotation=90, fontsize=7, color="0.4", va="bottom")
    _branches(ax)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(D31)
    ax.set_ylim(0, TWO_PI)
    width = "none" if sweep["width"] is None else f"{sweep['width']:.4g}"
    ax.set_title(f"hysteresis width {width} (loop: {sweep['loop']})", fontsize=9)
    ax.legend(loc="upper right", fontsize=7)


def fig6a(data: dict[str, Any], path: Path) -> None:
    fig, (top, mid, bottom) = plt.subplots(3, 1, figsize=(7.5, 10))
    for ax, key, what in ((top, "full", "0.70 → 0.62 → 0.70 (metachronal start)"),
                          (mid, "up_full", "0.62 → 0.70 → 0.62 (tripod start)")):  # fmt: skip
        s = data["series"].get(key)
        if s is None:
            continue
        ax.plot(s["d31_times_s"], s["d31"], "k.", ms=2.5)
        _branches(ax)
        ax.set_xlabel("time (s)")
        ax.set_ylabel(D31)
        ax.set_ylim(0, TWO_PI)
        twin = ax.twinx()
        twin.plot(s["d31_times_s"], s["value"], color="tab:orange", lw=1)
        twin.set_ylabel("duty factor β", color="tab:orange")
        ax.set_title(f"Δ31 at leg-1 touchdowns while β goes {what}", fontsize=9)
    s = data["series"]["full"]
    _sweep_axes(bottom, data["sweep"], s, "duty factor β",
                {"↓": 0.645, "↑": 0.67})  # fmt: skip
    up = data["series"].get("up_full")
    if up is not None:
        bottom.plot(up["value"], up["d31"], ".", ms=1.5, color="tab:purple", zorder=1,
                    label="tripod start at 0.62 ⇄")  # fmt: skip
        for tr in data.get("sweep_up", {}).get("first_leg", [])[:1]:
            bottom.axvline(tr["value"], color="tab:purple", lw=1.2, label=f"ours {tr['value']:.4g}")
        bottom.legend(loc="upper right", fontsize=7)
    h = data["series"]["half_rate"]
    bottom.plot(h["value"], h["d31"], ".", ms=1.2, color="0.75", zorder=0, label="half rate")
    rc = data["rate_check"]
    shifts = ", ".join("n/a" if x is None else f"{x:.4f}" for x in rc["shift"].values())
    bottom.set_title(bottom.get_title() + f"; half rate moves the transitions by {shifts} "
                     f"(tolerance {rc['tolerance']})", fontsize=8)  # fmt: skip
    _save(fig, path)


def fig6b(data: dict[str, Any], path: Path) -> None:
    fig, (top, ax) = plt.subplots(2, 1, figsize=(8, 5), sharex=True,
                                  gridspec_kw={"height_ratios": [1, 2]})  # fmt: skip
    top.plot(data["d31_times_s"], data["d31"], "k.-", ms=4, lw=0.6)
    _branches(top)
    top.set_ylim(0, TWO_PI)
    top.set_ylabel(D31)
    for row, leg in enumerate(LEG_ROWS):
        spans = [(a, b - a) for a, b in data["stance"][leg]]
        ax.broken_barh(spans, (len(LEG_ROWS) - 1 - row - 0.35, 0.7), color=LEG_COLOURS[leg])
    ax.set_yticks(range(len(LEG_ROWS)), [f"leg {leg + 1}" for leg in reversed(LEG_ROWS)])
    for a in (top, ax):
        a.axvline(data["centre_s"], color="k", lw=0.8, ls="--")
    ax.set_xlim(data["t0_s"], data["t1_s"])
    ax.set_xlabel("time (s); bars: stance")
    top.set_title(f"footprints across the metachronal-to-tripod transition ({data['centre']})",
                  fontsize=9)  # fmt: skip
    _save(fig, path)


def _heading_note(sweep: dict[str, Any]) -> str:
    h = sweep.get("max_heading_deg")
    return "" if h is None else f"; body turned up to {h:.0f}°"


def fig9(data: dict[str, Any], path: Path, xlabel: str, note: str) -> None:
    other = data.get("paper_ground")
    fig, axes = plt.subplots(2 if other else 1, 1, figsize=(7, 9 if other else 4.5), squeeze=False)
    ax = axes[0, 0]
    _sweep_axes(ax, data["sweep"], data["series"], xlabel)
    where = f"{data.get('ground', 'constraint')} ground"
    ax.set_title(ax.get_title() + f"; β = {data['beta']}, {where}{_heading_note(data['sweep'])}"
                 f"\npaper: {note}", fontsize=9)  # fmt: skip
    if other:
        ax = axes[1, 0]
        _sweep_axes(ax, other["sweep"], other["series"], xlabel)
        ax.set_title(ax.get_title() + f"; the paper's ground{_heading_note(other['sweep'])}",
                     fontsize=9)  # fmt: skip
    _save(fig, path)


def ablation(data: dict[str, Any], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(6.5, 3.8))
    for r in data["runs"]:
        if r["error"] is None:
            ax.plot(range(len(r["d31"])), r["d31"], ".-", ms=3, lw=0.6)
    s = data["summary"]
    drift = "n/a" if s["max_drift_rad"] is None else f"{s['max_drift_rad']:.2g}"
    ax.set_title(f"without phase resetting: Δ31 stays where it starts (max drift {drift} rad)",
                 fontsize=9)  # fmt: skip
    ax.set_xlabel("gait cycle n (leg-1 touchdowns)")
    ax.set_ylabel(D31)
    ax.set_ylim(0, TWO_PI)
    _save(fig, path)


def draw(name: str, data: dict[str, Any], path: Path, paper: PaperValues) -> None:
    """Draw the figure `name` (fig5, fig6a, fig6b, fig9a, fig9b, ablation) from its data into
    `path`; Figs. 7-8 are drawn from the drift surface (`surface_figures`)."""
    drawers: dict[str, Callable[[dict[str, Any], Path], None]] = {
        "fig5": fig5,
        "fig6a": fig6a,
        "fig6b": fig6b,
        "fig9a": lambda d, p: fig9(d, p, "body mass (g)",
                                   "heavy → tripod, light → metachronal, with hysteresis"),
        "fig9b": lambda d, p: fig9(d, p, "slope angle (deg), uphill +",
                                   "uphill → tripod, downhill → metachronal, with hysteresis"),
        "ablation": ablation,
    }  # fmt: skip
    drawers[name](data, path)

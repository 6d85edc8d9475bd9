"""Figures labelled like the paper's, with the paper's stated values marked for comparison.

Matplotlib with the Agg backend: files only, no display. File I/O lives here and in the CLI,
never in the physics.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from sim_core.calibration import (
    METACHRONAL_BRANCH,
    TRIPOD_BRANCH,
    Outcome,
    ReturnMap,
)
from sim_core.experiments import map_fixed_points
from sim_core.spec import RunResult


def plot_fig5(results: Mapping[float, Sequence[RunResult]], path: Path) -> None:
    """Delta31 at leg-1 touchdowns for several initial values, one panel per beta (Fig. 5)."""
    fig, axes = plt.subplots(1, len(results), figsize=(5 * len(results), 3.6), sharey=True)
    axes = [axes] if len(results) == 1 else list(axes)
    for ax, (beta, runs) in zip(axes, results.items(), strict=True):
        for r in runs:
            if not r.diverged:
                ax.plot(range(len(r.d31)), r.d31, ".", ms=2.5)
        ax.axhline(TRIPOD_BRANCH, color="k", ls="--", lw=0.8, label="paper tripod 2.9")
        ax.axhline(METACHRONAL_BRANCH, color="gray", ls=":", lw=0.8, label="paper metachronal 1.9")
        ax.set_title(f"beta = {beta}")
        ax.set_xlabel("gait cycle (leg-1 touchdowns)")
        ax.set_ylim(0, 2 * math.pi)
    axes[0].set_ylabel("Delta31 (rad)")
    axes[0].legend(loc="lower right", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_return_maps(maps: Sequence[ReturnMap], path: Path) -> None:
    """Delta31(n) -> Delta31(n+4) with the diagonal and fixed points (Fig. 7 construction)."""
    fig, axes = plt.subplots(1, len(maps), figsize=(4.2 * len(maps), 4.2))
    axes = [axes] if len(maps) == 1 else list(axes)
    for ax, rm in zip(axes, maps, strict=True):
        ax.plot(rm.x, rm.y, ".", ms=2, alpha=0.5)
        ax.plot([0, 2 * math.pi], [0, 2 * math.pi], "k-", lw=0.8)
        for fp in map_fixed_points(rm):
            ax.plot(fp.d31, fp.d31, "o", ms=8, mfc="k" if fp.stable else "w", mec="k", zorder=5)
        ax.set_title(f"beta = {rm.beta}")
        ax.set_xlabel("Delta31 n (rad)")
        ax.set_xlim(0, 2 * math.pi)
        ax.set_ylim(0, 2 * math.pi)
        ax.set_aspect("equal")
    axes[0].set_ylabel(f"Delta31 n+{maps[0].lag} (rad)")
    fig.suptitle("return maps; solid: stable fixed point, open: unstable", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_sensitivity(
    sens: dict[str, dict[str, list[Outcome]]], path: Path, rel: float = 0.10
) -> None:
    """Tornado chart: how +-rel of each parameter moves the branch census at each beta."""
    names = [n for n in sens if n != "base"]
    base = sens["base"]["0"]
    betas = [o.beta for o in base]
    gaits = {b: ("tripod" if b < 0.66 else "metachronal") for b in betas}
    fig, axes = plt.subplots(1, len(betas), figsize=(5.5 * len(betas), 0.35 * len(names) + 1.5))
    axes = [axes] if len(betas) == 1 else list(axes)
    for ax, (k, beta) in zip(axes, enumerate(betas), strict=True):
        g = gaits[beta]
        n0 = base[k].branch(g)[0]
        for row, name in enumerate(names):
            for label, color in (("-", "tab:blue"), ("+", "tab:red")):
                if label in sens[name]:
                    n = sens[name][label][k].branch(g)[0]
                    ax.barh(row, n - n0, left=n0, color=color, alpha=0.6, height=0.35)
        ax.axvline(n0, color="k", lw=0.8)
        ax.set_yticks(range(len(names)), names, fontsize=8)
        total = len(base[k].finals)
        ax.set_xlim(0, total)
        ax.set_xlabel(f"runs (of {total}) ending {g}, beta = {beta}")
    axes[0].set_title(f"blue: parameter -{rel:.0%}, red: +{rel:.0%}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)

"""The soft-leg regime's drift surface at beta 0.60-0.72 beside today's (issue 52, point 2),
and the surface checked against settled free walks in this regime (point 1).

Usage: python -m lab.campaigns.soft_legs_surface
Runs `drift_surface` with `named_params("soft_legs")` and the protocol of docs/figures/surface.json
(band pass on) on 2 local workers, cached in out/cache; writes docs/studies/surface_soft_legs.json
(kept out of the results folder: a DriftSurface records no model parameters, and the viewer would
take it for the defaults' surface) and docs/studies/surface_soft_legs.png; prints the zeros per
beta beside today's, and whether each settled walk of docs/studies/soft_legs.json ends within
0.05 rad of a stable zero.
"""

from __future__ import annotations

import json
import time
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from sim_core import ResultCache, drift_surface, get_backend
from sim_core.contract import DriftSurface, SurfaceConfig
from sim_core.research import named_params

BETAS = [round(0.60 + 0.01 * k, 2) for k in range(13)]
STUDIES = Path("docs/studies")
TODAY = Path("docs/figures/surface.json")
NEAR_RAD = 0.05  # a walk's final "on" a zero: the finder's one-attractor distance


def zeros_text(s: DriftSurface, beta: float) -> str:
    zs = [z for z in s.zeros_at(beta) if 1.4 <= z.d31 <= 3.4]
    return " ".join(f"{'S' if z.stable else 'U'}{z.d31:.2f}{'' if z.resolved else '?'}" for z in zs)


def main() -> None:
    cfg = replace(SurfaceConfig(), band_pass=True)
    t = time.perf_counter()
    soft = drift_surface(BETAS, cache=ResultCache("out/cache"), backend=get_backend("local", 2),
                         config=cfg, params=named_params("soft_legs"))  # fmt: skip
    wall = time.perf_counter() - t
    (STUDIES / "surface_soft_legs.json").write_text(soft.model_dump_json())
    today = DriftSurface.model_validate_json(TODAY.read_text())
    print(f"soft-leg surface: {len(BETAS)} betas, {soft.sim_s:.0f} simulated s in {wall:.0f} s")
    print("| beta | today's defaults | soft legs |\n|---|---|---|")
    for b in BETAS:
        print(f"| {b:.2f} | {zeros_text(today, b)} | {zeros_text(soft, b)} |")
    walks = json.loads((STUDIES / "soft_legs.json").read_text())["rows"]
    print("\n| step | beta | from | final | settled | nearest stable zero (same beta) |")
    print("|---|---|---|---|---|---|")
    for w in walks:
        b = w["beta"]
        if not any(abs(b - x) < 1e-9 for x in BETAS):
            continue
        stable = [z.d31 for z in soft.zeros_at(b) if z.stable]
        near = min(stable, key=lambda x: abs(x - w["final"])) if stable else None
        hit = near is not None and abs(near - w["final"]) <= NEAR_RAD
        zero = "none" if near is None else f"{near:.3f}" + (" (on it)" if hit else "")
        settled = "yes" if w["settled"] else "no"
        print(f"| {w['step']} | {b} | {w['start']} | {w['final']:.3f} | {settled} | {zero} |")
    fig, ax = plt.subplots(figsize=(8, 5))
    for s, colour, name in ((today, "0.5", "today's defaults"), (soft, "tab:red", "soft legs")):
        for kind in (True, False):
            zs = [z for z in s.zeros if z.stable is kind and 1.3 <= z.d31 <= 3.5]
            ax.scatter([z.beta for z in zs], [z.d31 for z in zs], s=22, color=colour,
                       facecolors=colour if kind else "none",
                       label=f"{name}: {'stable' if kind else 'unstable'} zero")  # fmt: skip
    ax.axvline(0.645, ls="--", color="tab:blue", lw=0.8, label="paper: metachronal -> tripod")
    ax.axvline(0.67, ls="--", color="tab:orange", lw=0.8, label="paper: tripod -> metachronal")
    ax.set_xlabel("duty factor β")
    ax.set_ylabel("Δ31 (rad)")
    ax.set_title("drift-surface zeros: soft legs beside today's defaults (3 g, level, constraint)")
    # where the pinned surface and free walking disagree, the walk wins (docs/studies/soft_legs.md)
    walked = [w for w in walks if w["settled"] and w["step"] == "dt"]
    ax.scatter([w["beta"] for w in walked], [w["final"] for w in walked], marker="x", s=40,
               color="k", label="soft legs: settled 40 s walk (decides here)")  # fmt: skip
    ax.text(0.01, 0.01, "soft legs: the pin misses states walks hold (0.64, 0.62-0.66 upper)",
            transform=ax.transAxes, fontsize="small")  # fmt: skip
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.savefig(STUDIES / "surface_soft_legs.png", dpi=110, bbox_inches="tight")


if __name__ == "__main__":
    main()

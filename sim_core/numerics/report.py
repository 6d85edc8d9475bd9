"""What `insect-gait numerics` shows: the Pareto chart, the stability map and the table of
docs/NUMERICS.md, all drawn from one grid (`numerics.grid_study`) so that figure, table and
data never disagree.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from sim_core.docsections import replace_section
from sim_core.numerics.convergence import (
    PENALTY_GROUND,
    STEP_TOUCHDOWN,
    TARGET_SPEEDUP,
    TOLERANCE_RAD,
    GridPoint,
)

SECTION = "numerics"  # the generated section of docs/NUMERICS.md


def _short_kind(failure: str) -> str:
    """'contact chatter' -> 'chatter', 'unstable (MuJoCo warning)' -> 'unstable', 'flip'..."""
    return "chatter" if "chatter" in failure else failure.split()[0]


def _ran(pt: GridPoint) -> bool:
    """Every run went the whole way (it may still fail, e.g. by chattering): its cost counts."""
    return pt.error_rad is not None and pt.wall_per_sim_s > 0


def _speedup(pt: GridPoint, ref_cost: object) -> float | None:
    """How many times cheaper than the timed reference, where pt's runs went the whole way."""
    return ref_cost / pt.wall_per_sim_s if isinstance(ref_cost, float) and _ran(pt) else None


def grid_markdown(points: Sequence[GridPoint], info: Mapping[str, object]) -> str:
    """The grid as a markdown table, one row per configuration, with its speed-up against the
    paper's RK4 at 2e-5 s when the reference was timed."""
    ref_cost = info.get("reference_wall_per_sim_s")
    paper_drift = info.get("reference_drift_error")
    lines = []
    if isinstance(ref_cost, float):
        lines.append(
            f"Reference (the paper's RK4 at 2e-5 s): {ref_cost:.3f} wall s per simulated s, "
            f"one simulation; its own drift error against RK4 at 1e-5 s: "
            + (f"{paper_drift:.4f} rad per cycle." if isinstance(paper_drift, float) else "-.")
        )
        lines.append("")
    lines += [
        "| configuration | dt (s) | status | outcome error (rad) | drift error (rad/cycle) "
        "| wall s per sim s | cheaper than the paper's RK4 | batch sim s per wall s "
        "| worst slip | re-touches per stance | failure |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]

    def num(x: float | None, fmt: str) -> str:
        return "-" if x is None else format(x, fmt)

    for pt in points:
        speedup = _speedup(pt, ref_cost)
        ratio = "-" if speedup is None else f"{speedup:.1f}x"
        status = f"**{pt.status}**" if pt.status == "ok" else pt.status
        lines.append(
            f"| {pt.label} | {pt.dt_s:g} | {status} | {num(pt.error_rad, '.3f')} "
            f"| {num(pt.drift_error, '.4f')} "
            f"| {num(pt.wall_per_sim_s if _ran(pt) else None, '.3f')} | {ratio} "
            f"| {num(pt.batch_sim_s_per_wall_s, '.2f')} "
            f"| {num(None if pt.max_slip is None else 100 * pt.max_slip, '.1f')}"
            f"{'' if pt.max_slip is None else '%'} | {num(pt.max_retouches, '.2f')} "
            f"| {pt.failure or ''} |"
        )
    return "\n".join(lines)


def save_grid(path: Path, points: Sequence[GridPoint], info: Mapping[str, object]) -> None:
    """numerics.json: the info dict plus one row per configuration (with status and label)."""
    rows = [dataclasses.asdict(p) | {"status": p.status, "label": p.label} for p in points]
    path.write_text(json.dumps(dict(info) | {"grid": rows}, indent=1))


def load_grid(path: Path) -> tuple[list[GridPoint], dict[str, object]]:
    """The grid and its info back from the numerics.json that `insect-gait numerics` wrote."""
    data = json.loads(path.read_text())
    names = {f.name for f in dataclasses.fields(GridPoint)}
    points = []
    for row in data.pop("grid"):
        fields: dict[str, Any] = {k: v for k, v in row.items() if k in names}
        fields["finals"] = tuple(fields.get("finals", ()))
        points.append(GridPoint(**fields))
    return points, data


def update_numerics_doc(text: str, points: Sequence[GridPoint], info: Mapping[str, object]) -> str:
    """docs/NUMERICS.md with its generated grid table replaced."""
    return replace_section(text, SECTION, grid_markdown(points, info))


def plot_grid(
    points: Sequence[GridPoint],
    pareto_path: Path,
    map_path: Path,
    info: Mapping[str, object] | None = None,
) -> None:
    """Pareto chart (cost vs outcome error and vs drift error, failures marked) and the
    stability map; with grid_study's info, the paper's RK4 cost, the 20x target and the
    paper's own drift error are drawn, and map cells give each configuration's speed-up."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    markers = {"euler": "o", "implicit": "s", "implicitfast": "^", "rk4": "D", "discrete": "P",
               f"implicitfast ({STEP_TOUCHDOWN[0]})": "v",
               f"implicitfast ({PENALTY_GROUND[0][0]})": "*",
               f"rk4 ({PENALTY_GROUND[0][0]})": "X"}  # fmt: skip
    colors = {"ok": "tab:green", "inaccurate": "tab:orange", "fails": "tab:red"}
    for pt in points:
        y = pt.error_rad if pt.error_rad is not None else math.pi
        kw = {"marker": markers.get(pt.label, "o"), "color": colors[pt.status], "s": 40}
        ax.scatter(pt.wall_per_sim_s, max(y, 1e-4), **kw)
        ax.annotate(f"{pt.dt_s:g}", (pt.wall_per_sim_s, max(y, 1e-4)), fontsize=6,
                    xytext=(3, 3), textcoords="offset points")  # fmt: skip
        if pt.drift_error:  # None: not measured; 0: the drift reference itself
            ax2.scatter(pt.wall_per_sim_s, max(pt.drift_error, 1e-5), **kw)
            ax2.annotate(f"{pt.dt_s:g}", (pt.wall_per_sim_s, max(pt.drift_error, 1e-5)),
                         fontsize=6, xytext=(3, 3), textcoords="offset points")  # fmt: skip
    ax.axhline(TOLERANCE_RAD, color="k", ls="--", lw=0.8)
    info = info or {}
    ref_cost = info.get("reference_wall_per_sim_s")
    if isinstance(ref_cost, float):
        for a in (ax, ax2):
            a.axvline(ref_cost, color="tab:blue", lw=0.8)
            a.axvline(ref_cost / TARGET_SPEEDUP, color="tab:blue", ls=":", lw=0.8)
        ax.annotate("paper's RK4 2e-5 s", (ref_cost, TOLERANCE_RAD), fontsize=7, rotation=90,
                    color="tab:blue", xytext=(-9, 8), textcoords="offset points")  # fmt: skip
        ax.annotate(f"{TARGET_SPEEDUP:g}x cheaper", (ref_cost / TARGET_SPEEDUP, TOLERANCE_RAD),
                    fontsize=7, rotation=90, color="tab:blue", xytext=(-9, 8),
                    textcoords="offset points")  # fmt: skip
    paper_drift = info.get("reference_drift_error")
    if isinstance(paper_drift, float):
        ax2.axhline(paper_drift, color="tab:blue", ls="--", lw=0.8)
        ax2.annotate(f"paper's RK4 2e-5 s: {paper_drift:.4f}", (0.02, paper_drift), fontsize=7,
                     color="tab:blue", xycoords=("axes fraction", "data"), xytext=(0, 3),
                     textcoords="offset points")  # fmt: skip
    for a in (ax, ax2):
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("wall seconds per simulated second (one simulation)")
    ax.set_ylabel("worst Delta31 outcome error vs RK4 2e-5 s (rad)")
    ax2.set_ylabel("worst return-map drift error vs RK4 1e-5 s (rad per cycle)")
    for name, m in markers.items():
        ax.scatter([], [], marker=m, color="gray", label=name)
    for label, c in (("ok", "tab:green"), ("inaccurate", "tab:orange"), ("fails (plotted at pi)",
                     "tab:red")):  # fmt: skip
        ax.scatter([], [], color=c, label=label)
    ax.legend(fontsize=7)
    ax.set_title("outcomes after a fixed time; dashed: tolerance 0.05 rad; labels: dt (s)",
                 fontsize=9)  # fmt: skip
    ax2.set_title("drift per gait cycle at fixed Delta31 (well conditioned); configurations "
                  "that run", fontsize=9)  # fmt: skip
    fig.tight_layout()
    fig.savefig(pareto_path, dpi=120)
    plt.close(fig)

    integs = sorted({p.label for p in points})
    dts = sorted({p.dt_s for p in points})
    code = {"ok": 0, "inaccurate": 1, "fails": 2}
    grid = np.full((len(integs), len(dts)), np.nan)
    for pt in points:
        grid[integs.index(pt.label), dts.index(pt.dt_s)] = code[pt.status]
    fig, ax = plt.subplots(figsize=(9, 3.4))
    cmap = matplotlib.colors.ListedColormap(["tab:green", "tab:orange", "tab:red"])
    ax.imshow(grid, cmap=cmap, vmin=0, vmax=2, aspect="auto")
    ax.set_xticks(range(len(dts)), [f"{d:g}" for d in dts])
    ax.set_yticks(range(len(integs)), integs)
    ax.set_xlabel("timestep (s)")
    by_cell = {(p.label, p.dt_s): p for p in points}
    for i in range(len(integs)):
        for j in range(len(dts)):
            if np.isfinite(grid[i, j]):
                text = ["ok", "inacc.", "fails"][int(grid[i, j])]
                pt = by_cell[(integs[i], dts[j])]
                if pt.failure:
                    text += f": {_short_kind(pt.failure)}"
                if (speedup := _speedup(pt, ref_cost)) is not None:
                    text += f"\n{speedup:.1f}x"
                ax.text(j, i, text, ha="center", va="center", fontsize=7)
    title = "stability map: ok (within 0.05 rad, same gaits), inaccurate, fails (why)"
    if isinstance(ref_cost, float):
        title += "\nNx: how many times cheaper than the paper's RK4 at 2e-5 s (one simulation)"
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(map_path, dpi=120)
    plt.close(fig)

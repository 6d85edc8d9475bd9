"""PNG figures and CSV tables of stored results, drawn on request in the API's thread pool.

Figures use matplotlib's object API with the Agg canvas (no pyplot), which keeps no global state
and so is safe in several request threads at once.
"""

from __future__ import annotations

import csv
import io
import math
from typing import Any

TWO_PI = 2.0 * math.pi


def records_csv(records: list[dict[str, Any]]) -> str:
    """Columns in first-seen order over all rows, so rows of different shapes still line up."""
    columns: list[str] = []
    for row in records:
        columns.extend(k for k in row if k not in columns)
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    for row in records:
        writer.writerow({k: _cell(v) for k, v in row.items()})
    return buf.getvalue()


def _cell(v: Any) -> Any:
    if isinstance(v, list | dict):
        return repr(v)
    return "" if v is None else v


def _d31_axis(ax: Any, axis: str = "y") -> None:
    ticks = [0, math.pi / 2, math.pi, 3 * math.pi / 2, TWO_PI]
    labels = ["0", "π/2", "π", "3π/2", "2π"]
    if axis == "y":
        ax.set_ylim(0, TWO_PI)
        ax.set_yticks(ticks, labels)
    else:
        ax.set_xlim(0, TWO_PI)
        ax.set_xticks(ticks, labels)


def figure_png(job: dict[str, Any], result: dict[str, Any]) -> bytes:
    """One figure per kind: Δ31 over touchdowns (run), the return map, Δ31 against β."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.8), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    kind = job["kind"]
    spec = job["spec"]
    records = result.get("records", [])
    if kind == "run":
        for d0, run in zip(spec.get("d31_init", []), result.get("runs", []), strict=False):
            d31 = run.get("d31") or []
            ax.plot(range(len(d31)), d31, marker="o", ms=3, label=f"Δ31(0) = {d0:.2f}")
        ax.set_xlabel("leg-1 touchdown n")
        ax.set_ylabel("Δ31 (rad)")
        _d31_axis(ax)
        ax.set_title(f"run: β = {spec.get('beta')}, {spec.get('duration_s')} s")
        if 0 < len(result.get("runs", [])) <= 12:
            ax.legend(fontsize="small")
    elif kind == "return_map":
        xs = [r["d31_n"] for r in records]
        ys = [r["d31_n_plus_lag"] for r in records]
        ax.scatter(xs, ys, s=8)
        ax.plot([0, TWO_PI], [0, TWO_PI], color="grey", lw=0.8)
        lag = result.get("lag", spec.get("lag"))
        ax.set_xlabel("Δ31[n] (rad)")
        ax.set_ylabel(f"Δ31[n+{lag}] (rad)")
        _d31_axis(ax, "x")
        _d31_axis(ax)
        ax.set_title(f"return map: β = {spec.get('beta')}")
    else:
        key = "d31_after_transient" if kind == "bifurcation" else "d31_final"
        pts = [(r["beta"], r[key]) for r in records if r.get(key) is not None]
        ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=6)
        ax.set_xlabel("β")
        ax.set_ylabel("Δ31 (rad)")
        _d31_axis(ax)
        ax.set_title(kind)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue()

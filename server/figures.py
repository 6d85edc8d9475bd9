"""PNG figures and CSV tables of stored results, drawn on request in the API's thread pool.

Figures use matplotlib's object API with the Agg canvas (no pyplot), which keeps no global state
and so is safe in several request threads at once.
"""

from __future__ import annotations

import csv
import io
import math
from typing import Any

from sim_core.contract import LEG_NAMES

TWO_PI = 2.0 * math.pi


def records_csv(records: list[dict[str, Any]], columns: list[str] | None = None) -> str:
    """`columns` first (the header an empty table still has), then any others in first-seen
    order over all rows, so rows of different shapes still line up."""
    columns = list(columns or [])
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


LEG_LABELS = list(LEG_NAMES)  # paper legs 1..6


def figure_png(job: dict[str, Any], result: dict[str, Any]) -> bytes:
    """One figure per kind: Δ31 over touchdowns (run; with its time series: Δ31 over time,
    the footfall of the first run and the body's path), the return map, Δ31 against β, and
    Δ31 against the swept parameter (hysteresis)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    kind = job["kind"]
    spec = job["spec"]
    series = kind == "run" and "series" in result
    fig = Figure(figsize=(6.4, 9.6) if series else (6.4, 4.8), dpi=100)
    FigureCanvasAgg(fig)
    if series:
        ax, ax_foot, ax_pos = fig.subplots(3, 1)
    else:
        ax = fig.add_subplot()
    records = result.get("records", [])
    if kind == "run":
        for d0, run in zip(spec.get("d31_init", []), result.get("runs", []), strict=False):
            d31 = run.get("d31") or []
            xs = run.get("d31_times_s") if series else range(len(d31))
            ax.plot(xs, d31, marker="o", ms=3, label=f"Δ31(0) = {d0:.2f}")
        ax.set_xlabel("time at leg-1 touchdown (s)" if series else "leg-1 touchdown n")
        ax.set_ylabel("Δ31 (rad)")
        _d31_axis(ax)
        ax.set_title(f"run: β = {spec.get('beta')}, {spec.get('duration_s')} s")
        if 0 < len(result.get("runs", [])) <= 12:
            ax.legend(fontsize="small")
        if series:
            _footfall(ax_foot, result["runs"][0])
            _body_path(ax_pos, result["runs"])
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
    elif kind == "hysteresis":
        for leg, colour in (("first", "tab:blue"), ("second", "tab:red")):
            pts = [(r["value"], r["d31"]) for r in records if r["leg"] == leg]
            ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=6, color=colour,
                       label=f"{'start → turn' if leg == 'first' else 'turn → start'}")  # fmt: skip
        summary = result.get("summary") or {}
        for leg, style in (("first_leg", "--"), ("second_leg", ":")):
            for tr in summary.get(leg) or []:
                if isinstance(tr, dict) and tr.get("value") is not None:
                    ax.axvline(tr["value"], ls=style, color="grey", lw=0.8)
        ax.set_xlabel(str(result.get("parameter", spec.get("parameter"))))
        ax.set_ylabel("Δ31 (rad)")
        _d31_axis(ax)
        ax.set_title(f"hysteresis sweep: {spec.get('start')} → {spec.get('turn')} → back")
        ax.legend(fontsize="small")
    elif kind in ("bifurcation", "atlas"):
        _finder_points(ax, records)
    else:
        pts = [(r["beta"], r["d31_final"]) for r in records if r.get("d31_final") is not None]
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


FINDER_MARKERS = {  # kind -> (marker, face colour, label)
    "stable": ("o", "k", "stable (settled runs)"),
    "unstable": ("o", "w", "unstable (basin border)"),
    "ghost": ("x", "tab:red", "ghost (slowest passage)"),
    "not settled": ("v", "0.6", "not settled"),
}


def _finder_points(ax: Any, records: list[dict[str, Any]]) -> None:
    """The finder's rows against beta: stable, unstable, ghosts, unsettled finals."""
    for kind, (marker, face, label) in FINDER_MARKERS.items():
        pts = [(r["beta"], r["d31"]) for r in records if r["kind"] == kind and r["d31"] is not None]
        if pts:
            edge = "k" if marker == "o" else face
            xs, ys = [p[0] for p in pts], [p[1] for p in pts]
            ax.scatter(xs, ys, s=22, marker=marker, facecolors=face, edgecolors=edge, label=label)
    ax.legend(fontsize="small")


def _footfall(ax: Any, run: dict[str, Any]) -> None:
    """Stance bars per leg (first run), paper legs 1..6 from the top."""
    times = run.get("times_s") or []
    stance = run.get("stance") or []
    if len(times) < 2:
        return
    dt = times[1] - times[0]
    for leg in range(6):
        spans: list[tuple[float, float]] = []
        for t, row in zip(times, stance, strict=False):
            if row[leg]:
                if spans and abs(spans[-1][0] + spans[-1][1] - t) < 1.5 * dt:
                    spans[-1] = (spans[-1][0], spans[-1][1] + dt)
                else:
                    spans.append((t, dt))
        ax.broken_barh(spans, (5 - leg - 0.4, 0.8), color="black")
    ax.set_yticks(range(6), LEG_LABELS[::-1])
    ax.set_xlabel("time (s)")
    ax.set_title("stance (first run)")


def _body_path(ax: Any, runs: list[dict[str, Any]]) -> None:
    for k, run in enumerate(runs[:12]):
        pos = run.get("body_pos_m") or []
        ax.plot(run.get("times_s") or [], [100.0 * p[0] for p in pos], label=f"run {k}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("body x (cm)")
    ax.set_title("body position along the slope")

"""`insect-gait reproduce`: the paper's Figs. 5-9 and the ablation, and the table of numbers.

One call lists the tasks of the asked-for figures (`sim_core.paper.figures`), runs the missing
ones on a backend (`sim_core.runs.backends`; results cached by content hash, so an interrupted run
resumes and a re-run only redraws), then writes for each figure a PNG, a JSON with the data
behind it and a CSV, and renders the reproduction table: the paper's value next to ours for
every number the paper states, with "reproduced?" computed from the data by the rules printed
under the table. The table goes to OUT/reproduce_table.md and, between the markers, into
docs/REPRODUCTION.md.
"""

from __future__ import annotations

import csv
import datetime
import json
import time
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from sim_core.docsections import markers, replace_section
from sim_core.model.gait import HEADING_KEPT_DEG
from sim_core.model.params import ModelParams
from sim_core.paper.analysis import PAPER_WINDOW
from sim_core.paper.figures import (
    BRANCH_TOL,
    FIGURES,
    Config,
    analyse,
    figure_tasks,
    finder_cells,
)
from sim_core.paper.fixedpoints import FinderOutput, find
from sim_core.paper.results import BIFURCATION_FILE
from sim_core.paper.search import task_runner
from sim_core.paper.values import PAPER
from sim_core.runs.backends import Backend, Executor, RunStats, run_tasks
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import Task, code_fingerprint, execute_chunk, params_hash

DOC_BEGIN, DOC_END = markers("reproduce")
STATE_FILE = "reproduce.json"
TABLE_FILE = "reproduce_table.md"
BETA_TOL = 0.01  # transitions and range ends within this (in beta) count as reproduced
SPEED_TOL = 0.10  # relative
NEUTRAL_TOL = 0.01  # rad: the largest drift of Delta31 without resetting that counts as neutral
GHOST_TOL = 0.3  # rad
RULES = (
    f"Rules: Fig. 5 runs settle within {BRANCH_TOL} rad of the paper's branch (yes: every run, "
    f"partly: some); transitions (the half-rate sweep) and range ends within {BETA_TOL} in "
    f"beta; speeds within {SPEED_TOL:.0%}; fixed points: the same stable/unstable pattern "
    f"inside {PAPER_WINDOW[0]}-{PAPER_WINDOW[1]} rad; ghosts within {GHOST_TOL} rad; "
    "directions: both ends in the paper's gait (partly: without a hysteresis loop); neutral: "
    f"Delta31 drifts < {NEUTRAL_TOL} rad without phase resetting."
)


def expand(figures: Iterable[str]) -> list[str]:
    """'all' -> every figure; otherwise the asked-for ones, in the paper's order."""
    asked = set(figures)
    if "all" in asked:
        return list(FIGURES)
    unknown = asked - set(FIGURES)
    if unknown:
        raise ValueError(f"unknown figure(s) {sorted(unknown)}; choose from {FIGURES} or all")
    return [f for f in FIGURES if f in asked]


@dataclass
class Report:
    figures: list[str]
    files: list[Path]
    stats: RunStats
    wall_s: float
    table: str
    summaries: dict[str, Any] = field(default_factory=dict)


def _add_stats(a: RunStats, b: RunStats) -> RunStats:
    return RunStats(a.tasks + b.tasks, a.computed + b.computed, a.cached + b.cached,
                    a.compute_s + b.compute_s)  # fmt: skip


def _cached(cache: ResultCache, t: Task) -> dict[str, Any]:
    hit = cache.get(t)
    if hit is None:
        raise KeyError(f"no result for task {t.key} in the cache")
    return hit


def _write_csv(path: Path, header: list[str], rows: list[list[Any]]) -> None:
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)


def _load_state(path: Path, identity: dict[str, Any]) -> dict[str, Any]:
    """Summaries of earlier runs into the same folder, if made with the same model and config."""
    try:
        state = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    if not isinstance(state, dict) or state.get("identity") != identity:
        return {}
    summaries = state.get("summaries")
    return summaries if isinstance(summaries, dict) else {}


def reproduce(
    figures: Sequence[str],
    cfg: Config,
    out: Path,
    cache_dir: Path,
    backend: Backend,
    *,
    params: ModelParams | None = None,
    doc: Path | None = None,
    progress: bool = True,
    executor: Executor = execute_chunk,
) -> Report:
    """Run (or load) the figures' tasks, write figures + data + table; see the module doc."""
    from sim_core.paper.plots import draw

    t0 = time.perf_counter()
    p = params or ModelParams()
    figs = expand(figures)
    tasks: list[Task] = [t for f in figs for t in figure_tasks(f, cfg, p)]
    cache = ResultCache(cache_dir)
    results, stats = run_tasks(tasks, cache, backend, cfg.chunk_size, progress, executor)
    # Figs. 7-8: the settled fixed-point finder, round by round through the same cache
    cells = finder_cells(figs, cfg)
    finder_stats = RunStats()
    run_fn = task_runner(cache, backend, p, chunk_size=cfg.chunk_size, progress=progress,
                      stats=finder_stats, executor=executor)  # fmt: skip
    found = {c.beta: c for c in find(cells, cfg.finder, run_fn)} if cells else {}
    stats = _add_stats(stats, finder_stats)

    def get(t: Task) -> dict[str, Any]:
        return results[t.key] if t.key in results else _cached(cache, t)

    out.mkdir(parents=True, exist_ok=True)
    identity = {"params": params_hash(p), "code": code_fingerprint(), "config": cfg.to_dict()}
    identity = json.loads(json.dumps(identity))  # as read back from the state file
    summaries = _load_state(out / STATE_FILE, identity)
    files: list[Path] = []
    for f in figs:
        for fd in analyse(f, cfg, p, get, found):
            meta = {"figure": fd.name, "identity": identity, "summary": fd.summary}
            (out / f"{fd.name}.json").write_text(json.dumps(meta | {"data": fd.data}))
            files.append(out / f"{fd.name}.json")
            for stem, (header, rows) in fd.csv.items():
                _write_csv(out / f"{stem}.csv", header, rows)
                files.append(out / f"{stem}.csv")
            draw(fd.name, fd.data, out / f"{fd.name}.png", PAPER)
            files.append(out / f"{fd.name}.png")
            if fd.name == "fig8":  # the viewer draws the live (beta, Delta31) point on this
                fo = FinderOutput(
                    source="insect-gait reproduce: Fig. 8, the settled fixed-point finder",
                    config=asdict(cfg.finder), cells=[found[b] for b in cfg.bif_betas],
                )  # fmt: skip
                (out / BIFURCATION_FILE).write_text(fo.model_dump_json())
                files.append(out / BIFURCATION_FILE)
            summaries[fd.name] = fd.summary
    wall = time.perf_counter() - t0
    run = {
        "figures": figs, "wall_s": wall, "backend": backend.name, "workers": backend.workers,
        "date": datetime.date.today().isoformat(), "config": cfg.name, **asdict(stats),
    }  # fmt: skip
    table = render_table(summaries, run, identity)
    state = {"identity": identity, "summaries": summaries, "last_run": run}
    (out / STATE_FILE).write_text(json.dumps(state, indent=1))
    (out / TABLE_FILE).write_text(table + "\n")
    files += [out / STATE_FILE, out / TABLE_FILE]
    if doc is not None:
        doc.write_text(update_doc(doc.read_text(), table))
    return Report(figs, files, stats, wall, table, summaries)


# --- the table ----------------------------------------------------------------------------------
Row = tuple[str, str, str, str]


def _b(x: float) -> str:
    """A beta as the paper writes it: 0.62, 0.645, 0.70."""
    return f"{x:.2f}" if round(x, 2) == x else f"{x:.3f}"


def _f(x: float | None, digits: int = 3) -> str:
    return "n/a" if x is None else f"{x:.{digits}g}"


def _counts(finals: list[float | None]) -> str:
    """'3.0 ×5, 0.2 ×2, unsettled ×1': where the runs ended, grouped to 0.1 rad."""
    groups: dict[str, int] = {}
    for x in finals:
        key = "unsettled" if x is None else f"{x:.1f}"
        groups[key] = groups.get(key, 0) + 1
    return ", ".join(f"{k} ×{n}" for k, n in groups.items())


def _verdict(ok: bool) -> str:
    return "yes" if ok else "**no**"


def _fig5_rows(s: dict[str, Any] | None) -> list[Row]:
    rows: list[Row] = []
    for key, name, paper in (("0.62", "tripod", PAPER.branch_tripod_rad),
                             ("0.7", "metachronal", PAPER.branch_metachronal_rad)):  # fmt: skip
        label = f"Fig. 5: Δ31 at β = {float(key):.2f} ({name})"
        b = None if s is None else s.get(key)
        if b is None:
            rows.append((label, f"{paper} rad", "not run", "not run"))
            continue
        ours = f"{b['hits']} of {b['runs']} runs within {BRANCH_TOL} rad"
        ours += "" if b["branch_rad"] is None else f", at {b['branch_rad']:.2f} rad"
        ours += f" (settled: {_counts(b['finals'])})"
        v = "yes" if b["hits"] == b["runs"] else ("partly" if b["hits"] else "**no**")
        rows.append((label, f"{paper} rad", ours, v))
    for beta, v_paper in PAPER.speed_cm_s:
        b = None if s is None else s.get(str(beta))
        label = f"speed at β = {beta:.2f} (eq. 2)"
        if b is None or b["speed_cm_s"] is None:
            rows.append((label, f"{v_paper} cm/s", "not run" if b is None else "n/a", "not run"))
            continue
        ok = abs(b["speed_cm_s"] - v_paper) <= SPEED_TOL * v_paper
        rows.append((label, f"{v_paper} cm/s", f"{b['speed_cm_s']:.2f} cm/s (median)",
                     _verdict(ok)))  # fmt: skip
    return rows


def _fig6_rows(s: dict[str, Any] | None) -> list[Row]:
    """Judged on the slower (half-rate) sweep, the closer to the paper's quasi-static one."""
    labels = {
        "first_leg": ("Fig. 6a: metachronal → tripod as β decreases", PAPER.transition_down),
        "second_leg": ("Fig. 6a: tripod → metachronal as β increases", PAPER.transition_up),
    }
    paper_width = PAPER.transition_up - PAPER.transition_down
    if s is None:
        return [(lab, f"β = {v}", "not run", "not run") for lab, v in labels.values()] + [
            ("Fig. 6a: hysteresis width", f"{paper_width:.3f}", "not run", "not run"),
            ("ramp slow enough (our check)", "—", "not run", "not run"),
        ]
    rc = s["rate_check"]
    rows: list[Row] = []
    for leg, (label, paper) in labels.items():
        slow, fast, zero = (rc["switch"]["half_rate"][leg], rc["switch"]["full"][leg],
                            rc["zero_rate"][leg])  # fmt: skip
        if slow is None:
            seen = "" if fast is None else f" at half rate (full rate: β = {fast:.4f})"
            rows.append((label, f"β = {paper}", "no transition detected" + seen, "**no**"))
            continue
        ours = f"β = {slow:.4f} at half rate (full rate {_f(fast, 4)}; rate → 0: {_f(zero, 4)})"
        rows.append((label, f"β = {paper}", ours, _verdict(abs(slow - paper) <= BETA_TOL)))
    down, up = rc["switch"]["half_rate"]["first_leg"], rc["switch"]["half_rate"]["second_leg"]
    if down is None or up is None:
        rows.append(("Fig. 6a: hysteresis width", f"{paper_width:.3f}", "no loop", "**no**"))
    else:
        width = up - down
        ok = width > 0 and abs(width - paper_width) <= BETA_TOL
        ours = f"{width:.4f} at half rate" + ("" if width > 0 else " (no loop: wrong order)")
        rows.append(("Fig. 6a: hysteresis width", f"{paper_width:.3f}", ours, _verdict(ok)))
    shifts = ", ".join("none" if x is None else f"{x:.4f}" for x in rc["shift"].values())
    rows.append((f"halving the ramp rate moves the transitions by < {rc['tolerance']} "
                 "(our check)", "—", f"moved {shifts}", _verdict(rc["ok"])))  # fmt: skip
    return rows


def _fig7_rows(s: dict[str, Any] | None) -> list[Row]:
    rows: list[Row] = []
    for beta, pat, gait in PAPER.fixed_points:
        paper = f"{len(pat.split())} ({pat}{', ' + gait if gait else ''})"
        label = f"Fig. 7: fixed points at β = {beta}"
        m = None if s is None else s.get(str(beta))
        if m is None:
            rows.append((label, paper, "not run", "not run"))
            continue
        fps = m["window_fixed_points"]
        where = ", ".join(f"{f['d31']:.2f}{'' if f['stable'] else ' (U)'}" for f in fps)
        ours = f"{len(fps)} ({m['window_pattern'] or 'none'}){': ' + where if where else ''}"
        unsettled = m.get("unsettled") or []
        if unsettled:
            ends = ", ".join(f"{u['final']:.2f}" for u in unsettled if u["final"] is not None)
            ours += f"; {len(unsettled)} run(s) not settled (at {ends})"
        ok = m["window_pattern"] == pat
        if ok and gait is not None:
            ok = all(f["gait"] == gait for f in fps if f["stable"])
        rows.append((label, paper, ours, _verdict(ok)))
    for beta, g in PAPER.ghosts_rad:
        label = f"Fig. 7: ghost at β = {beta}"
        m = None if s is None else s.get(str(beta))
        if m is None:
            rows.append((label, f"near {g} rad", "not run", "not run"))
            continue
        near = [x for x in m["ghosts"] if abs(x - g) <= GHOST_TOL]
        ours = ", ".join(f"{x:.2f}" for x in m["ghosts"]) or "none"
        rows.append((label, f"near {g} rad", ours, _verdict(bool(near))))
    return rows


def _fig8_rows(s: dict[str, Any] | None) -> list[Row]:
    rows: list[Row] = []
    for gait in ("tripod", "metachronal"):
        a, b = PAPER.tripod_stable if gait == "tripod" else PAPER.metachronal_stable
        label = f"Fig. 8: {gait} stable for β in"
        if s is None:
            rows.append((label, f"{_b(a)}-{_b(b)}", "not run", "not run"))
            continue
        br = s["branches"][gait]
        segs = "; ".join(f"{_b(lo)}-{_b(hi)}" for lo, hi in br["ranges"]) or "nowhere on the grid"
        folds = ", ".join(f"{f['beta']:.4f}±{f['half_width']:.4f}" for f in br["folds"])
        ours = segs + (f" (folds at {folds})" if folds else "")
        if s.get("unsettled"):
            ours += f"; {s['unsettled']} of {s['runs']} runs not settled"
        ends = br["ends"]
        ok = ends is not None and abs(ends[0] - a) <= BETA_TOL and abs(ends[1] - b) <= BETA_TOL
        rows.append((label, f"{_b(a)}-{_b(b)}", ours, _verdict(ok)))
    return rows


def _sweep_row(label: str, s: dict[str, Any] | None, paper: str, ends: tuple[str, str]) -> Row:
    if s is None:
        return (label, paper, "not run", "not run")
    lo_name, hi_name = ends  # what the start (lower) and turn (higher) values are called

    def said(x: dict[str, Any]) -> str:
        out = f"{hi_name}: {x['gait_at_turn']}, {lo_name}: {x['gait_at_start']}"
        out += f", loop: {x['loop']}" + (f" (width {x['width']:.3g})" if x["width"] else "")
        turned = x.get("max_heading_deg")
        if turned is not None and turned > HEADING_KEPT_DEG:
            out += f"; the body turned up to {turned:.0f} deg off the slope's line"
        return out

    ours = said(s)
    if s.get("paper_ground") is not None:
        ours += f". Paper's ground: {said(s['paper_ground'])}"
    right = s["gait_at_turn"] == "tripod" and s["gait_at_start"] == "metachronal"
    v = "yes" if right and s["loop"] else ("partly" if right else "**no**")
    return (label, paper, ours, v)


def table_rows(summaries: dict[str, Any]) -> list[Row]:
    s = summaries.get
    rows = _fig5_rows(s("fig5")) + _fig6_rows(s("fig6a")) + _fig7_rows(s("fig7"))
    rows += _fig8_rows(s("fig8"))
    rows.append(
        _sweep_row(
            "Fig. 9a: body mass",
            s("fig9a"),
            "heavy → tripod, light → metachronal, hysteresis",
            ("light", "heavy"),
        )
    )
    rows.append(_sweep_row("Fig. 9b: slope", s("fig9b"),
                           "uphill → tripod, downhill → metachronal, hysteresis",
                           ("downhill", "uphill")))  # fmt: skip
    ab = s("ablation")
    label = "no phase resetting: Δ31 neutral (Sec. IV)"
    if ab is None or ab["max_drift_rad"] is None:
        rows.append((label, "neutral", "not run", "not run"))
    else:
        ok = ab["max_drift_rad"] < NEUTRAL_TOL and not ab["diverged"]
        rows.append((label, "neutral", f"max drift {ab['max_drift_rad']:.2g} rad over "
                     f"{ab['runs']} runs", _verdict(ok)))  # fmt: skip
    return rows


def render_table(summaries: dict[str, Any], run: dict[str, Any], identity: dict[str, Any]) -> str:
    lines = ["| paper states | paper | ours | reproduced? |", "|---|---|---|---|"]
    lines += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in table_rows(summaries)]
    hit = sum(1 for r in table_rows(summaries) if r[3] == "yes")
    total = sum(1 for r in table_rows(summaries) if r[3] != "not run")
    lines += [
        "",
        f"{hit} of {total} rows reproduced. {RULES}",
        "",
        f"Generated by `insect-gait reproduce` on {run['date']} (config `{run['config']}`, "
        f"parameters `{identity['params']}`, physics code `{identity['code']}`): figures "
        f"{', '.join(run['figures'])} in **{run['wall_s']:.0f} s** wall time on the "
        f"`{run['backend']}` backend with {run['workers']} worker(s); {run['computed']} of "
        f"{run['tasks']} simulations computed, {run['cached']} from the cache; all results "
        f"together took {run['compute_s']:.0f} s of single-core compute.",
    ]
    return "\n".join(lines)


def update_doc(text: str, table: str) -> str:
    """Replace what lies between the reproduce markers (both must be present, in order)."""
    return replace_section(text, "reproduce", table)

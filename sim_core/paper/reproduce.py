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

from sim_core.contract.results import SURFACE_FILE, SURFACE_PENALTY_FILE
from sim_core.contract.values import PAPER
from sim_core.docsections import markers, replace_section
from sim_core.model.gait import HEADING_KEPT_DEG
from sim_core.model.params import ModelParams
from sim_core.model.version import PHYSICS_VERSION
from sim_core.paper.analysis import PAPER_WINDOW
from sim_core.paper.figures import BRANCH_TOL, FIGURES, ReproduceConfig, analyse, figure_tasks
from sim_core.paper.surface_check import variant_table
from sim_core.paper.surface_repro import (
    FREE_RUN_TOL,
    SurfaceStudy,
    surface_figure_data,
    surface_study,
)
from sim_core.runs.backends import Backend, Executor, RunStats, run_tasks
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import Task, execute_chunk, params_hash

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
    cfg: ReproduceConfig,
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
    if doc is not None:  # before the work, not after it: say now where the table cannot go
        _check_doc(doc.read_text(), surface="7" in figs or "8" in figs)
    tasks: list[Task] = [t for f in figs for t in figure_tasks(f, cfg, p)]
    cache = ResultCache(cache_dir)
    results, stats = run_tasks(tasks, cache, backend, cfg.chunk_size, progress, executor)

    def get(t: Task) -> dict[str, Any]:
        return results[t.key] if t.key in results else _cached(cache, t)

    # Figs. 7-8: the drift surface, its sample checks and the mechanism's surface on the
    # paper's ground, probe by probe through the same cache
    study = None
    if "7" in figs or "8" in figs:
        study = surface_study(cfg.surface_betas, cfg.surface, p, cache, backend,
                              progress=progress, executor=executor,
                              mechanism_refine=cfg.mechanism_refine, walks=cfg.walks,
                              last_pass_betas=cfg.last_pass_betas)  # fmt: skip
        stats = _add_stats(stats, study.stats)

    out.mkdir(parents=True, exist_ok=True)
    identity = {"params": params_hash(p), "physics": PHYSICS_VERSION, "config": cfg.to_dict()}
    identity = json.loads(json.dumps(identity))  # as read back from the state file
    summaries = _load_state(out / STATE_FILE, identity)
    files: list[Path] = []
    figure_data = [fd for f in figs if f not in ("7", "8") for fd in analyse(f, cfg, p, get)]
    if study is not None:
        figure_data += surface_figure_data(study, figs, cfg, p, get, out, PAPER, BETA_TOL)
    for fd in figure_data:
        meta = {"figure": fd.name, "identity": identity, "summary": fd.summary}
        (out / f"{fd.name}.json").write_text(json.dumps(meta | {"data": fd.data}))
        files.append(out / f"{fd.name}.json")
        for stem, (header, rows) in fd.csv.items():
            _write_csv(out / f"{stem}.csv", header, rows)
            files.append(out / f"{stem}.csv")
        if fd.name not in ("fig7", "fig8"):  # drawn from the surface by `surface_figure_data`
            draw(fd.name, fd.data, out / f"{fd.name}.png", PAPER)
        files.append(out / f"{fd.name}.png")
        summaries[fd.name] = fd.summary
    if study is not None:
        (out / SURFACE_FILE).write_text(study.surface.model_dump_json())
        (out / SURFACE_PENALTY_FILE).write_text(study.paper_ground.model_dump_json())
        files += [out / SURFACE_FILE, out / SURFACE_PENALTY_FILE, out / "mechanism.png"]
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
        text = update_doc(doc.read_text(), table)
        if study is not None:
            text = replace_section(text, "surface", surface_section(study, backend))
        doc.write_text(text)
    return Report(figs, files, stats, wall, table, summaries)


def _check_doc(text: str, *, surface: bool) -> None:
    """The doc holds the sections a run will write (the table; with Figs. 7-8 the surface's),
    else a ValueError naming the missing markers."""
    for name in ("reproduce", "surface") if surface else ("reproduce",):
        begin, end = markers(name)
        if begin not in text or end not in text:
            raise ValueError(f"the document has no {begin} ... {end} section for reproduce")


def surface_section(study: SurfaceStudy, backend: Backend) -> str:
    """What the surface behind Figs. 7-8 cost, and the protocol's checks on a sample."""
    s = study.surface
    floor = s.config.floor_rad
    return "\n".join([
        f"Figs. 7-8 read from the drift surface: {len(s.points)} probes ({s.sim_s:.0f} "
        f"simulated s) over {len(s.betas)} betas in {study.surface_wall_s:.0f} s wall; "
        f"{study.wall_s:.0f} s with the paper's ground's mechanism surfaces and the sample "
        f"checks ({study.stats.computed} probes computed, {study.stats.cached} read from the "
        f"cache), on the `{backend.name}` backend with {backend.workers} worker(s) "
        f"({datetime.date.today().isoformat()}).",
        "",
        f"The protocol on a sample (every difference within the {floor * 1e3:g} mrad noise "
        f"floor: {'yes' if study.checks_ok else '**no**'}):",
        "",
        variant_table(study.checks),
    ])  # fmt: skip


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
    """The surface's patterns (`surface_figures.fig7_rows`), the ghosts, and our check that
    the settled free runs end on the surface's stable zeros."""
    if s is None:
        rows: list[Row] = [
            (f"Fig. 7: fixed points at β = {b}", f"{len(pat.split())} ({pat})", "not run",
             "not run") for b, pat, _ in PAPER.fixed_points
        ]  # fmt: skip
        rows += [(f"Fig. 7: ghost at β = {b}", f"near {g} rad", "not run", "not run")
                 for b, g in PAPER.ghosts_rad]  # fmt: skip
        return rows
    rows = [(a, b, c, d) for a, b, c, d in s["pattern_rows"]]
    for beta, g in PAPER.ghosts_rad:
        label = f"Fig. 7: ghost at β = {beta}"
        m = s.get(str(beta))
        if m is None:
            rows.append((label, f"near {g} rad", "not run", "not run"))
            continue
        near = [x for x in m["ghosts"] if abs(x - g) <= GHOST_TOL]
        ours = ", ".join(f"{x:.2f}" for x in m["ghosts"]) or "none"
        rows.append((label, f"near {g} rad", ours, _verdict(bool(near))))
    per_beta = {k: v for k, v in s.items() if isinstance(v, dict)}
    outside = [f"{x:.2f} at {b}" for b, v in per_beta.items() for x in v["outside"]]
    runs = sum(len(v["finals"]) for v in per_beta.values()) - len(outside)
    off = [f"{x:.2f} at {b}" for b, v in per_beta.items() for x in v["off_zeros"]]
    unsettled = sum(v["unsettled"] for v in per_beta.values())
    ours = (f"{runs - len(off)} of {runs} settled runs in the held range within {FREE_RUN_TOL} "
            "rad of a stable zero")  # fmt: skip
    ours += f" (off: {', '.join(off)})" if off else ""
    ours += f"; outside the held range: {', '.join(outside)}" if outside else ""
    ours += f"; {unsettled} run(s) not settled" if unsettled else ""
    rows.append(("Fig. 7: free runs end on the surface's stable zeros (our check)", "—", ours,
                 _verdict(not off and runs > 0)))  # fmt: skip
    return rows


def _fig8_rows(s: dict[str, Any] | None) -> list[Row]:
    """The surface's stable ranges (`surface_figures.fig8_rows`) and our check of its protocol
    (K/3, dt/2) on a sample."""
    label = "drift surface: the pin at K/3 and dt/2 on a sample (our check)"
    if s is None:
        ranges = (("tripod", PAPER.tripod_stable), ("metachronal", PAPER.metachronal_stable))
        rows: list[Row] = [
            (f"Fig. 8: {g} stable for β in", f"{_b(a)}-{_b(b)}", "not run", "not run")
            for g, (a, b) in ranges
        ]
        return [*rows, (label, "—", "not run", "not run")]
    rows = [(a, b, c, d) for a, b, c, d in s["range_rows"]]
    rows += _off_grid_rows(s.get("off_grid"))
    worst = ", ".join(
        f"{k} {'n/a' if v is None else f'{v * 1e3:.2f}'}" for k, v in s["checks_worst"].items()
    )
    ours = f"largest drift differences (mrad/cycle): {worst}; floor {s['floor_rad'] * 1e3:g}"
    rows.append((label, "—", ours, _verdict(bool(s["checks_ok"]))))
    return rows


def _off_grid_rows(off: list[dict[str, Any]] | None) -> list[Row]:
    """Our check that Fig. 8's ranges hold between the grid's betas (issue 52, point 1):
    settled walks beside each range end, half a step inside (the gait should hold) and a step
    and a half outside (it should not)."""
    label = "Fig. 8: the ranges against settled walks off the grid (our check)"
    if off is None:  # a summary from before the walks
        return []
    if not off:
        return [(label, "—", "no range end inside the grid walked", "not run")]

    def said(o: dict[str, Any]) -> str:
        got = "undecided" if o["holds"] is None else "holds" if o["holds"] else "leaves"
        where = "" if o["final"] is None else f" ({o['final']:.2f})"
        want = "inside" if o["expected"] else "outside"
        return f"{o['gait']} at {o['beta']:g} ({want}): {got}{where}"

    agree = [o for o in off if o["holds"] is o["expected"]]
    ours = f"{len(agree)} of {len(off)} agree: " + "; ".join(said(o) for o in off)
    return [(label, "—", ours, _verdict(len(agree) == len(off)))]


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
    rows = [r for r in table_rows(summaries) if r[3] != "not run"]
    paper = [r for r in rows if r[1] != "—"]  # a row of ours has no paper value: a check
    checks = [r for r in rows if r[1] == "—"]
    hit = sum(1 for r in paper if r[3] == "yes")
    ok = sum(1 for r in checks if r[3] == "yes")
    lines += [
        "",
        f"{hit} of {len(paper)} of the paper's rows reproduced; {ok} of {len(checks)} of our "
        f"checks pass. {RULES}",
        "",
        f"Generated by `insect-gait reproduce` on {run['date']} (config `{run['config']}`, "
        f"parameters `{identity['params']}`, physics version `{identity['physics']}`): figures "
        f"{', '.join(run['figures'])} in **{run['wall_s']:.0f} s** wall time on the "
        f"`{run['backend']}` backend with {run['workers']} worker(s); {run['computed']} of "
        f"{run['tasks']} simulations computed, {run['cached']} from the cache; all results "
        f"together took {run['compute_s']:.0f} s of single-core compute.",
    ]
    return "\n".join(lines)


def update_doc(text: str, table: str) -> str:
    """Replace what lies between the reproduce markers (both must be present, in order)."""
    return replace_section(text, "reproduce", table)

"""Gait selection, third campaign (issue 22): the regime map and the step-one setting's checks.

Sub-commands (numbers and the commands that made them: docs/studies/gait_campaign3.md):

    finals  fixed-beta runs from given starts on a parameter set: final Delta31 (circular
            mean of the last quarter), drift per gait cycle there, landing share, speed, slip
    map     the regime map: attractors from starts 1.9 and 3.0 at beta 0.62 and 0.70 over
            (load per unit lift stiffness) x (centre of mass fore/aft) x (lift lag), with the
            open-loop drift (`probes.open_loop_drift`) beside each cell; JSON + figure
    robust  +-10% of each calibrated parameter: finals at the given betas and starts
    sweep   the paper's beta sweep (Fig. 6a) with `sim_core.sweep`, binned per 0.005

Parameter sets are `ModelParams()` (today's default) plus `--set name=value` overrides;
`STEP_ONE` names the adopted setting. Nothing here knows the target gait; beta enters only
through eq. 2 inside sim_core.

    python -m lab.campaigns.gait_campaign3 map --out docs/studies/regimes.json
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from lab.campaigns.gait_campaign2 import binned_legs, crossings, row, table_finals
from sim_core import (
    Backend,
    ModelParams,
    ResultCache,
    RunSpec,
    Task,
    default_cache_dir,
    get_backend,
    run_tasks,
    simulate_batch,
    sweep,
)
from sim_core.contract import Ramp, classify_gait
from sim_core.research import open_loop_drift, ramp_task

# The step-one candidate of issue 22 (fact 7, first row): lift joints 0.6x as stiff with
# damping on their own velocity (1 ms lag), a 0.5 mm lower stance, centre of mass 1 mm forward.
STEP_ONE: dict[str, Any] = {
    "kp_lift": 3e-3,
    "kd_lift": 3e-6,
    "velocity_feedforward_lift": 0.0,
    "stand_height": 6.5e-3,
    "com_offset_x": 1.0e-3,
}
# The map's runs are short (15-20 s); a start sliding through a ghost past a fold moves only
# 0.002-0.004 rad per cycle, under the 0.005 rule. The map calls a state an attractor
# only below this drift (true attractors measured 0.0000-0.0007 rad per cycle).
MAP_SETTLED = 0.001


def kind(final: float | None, beta: float) -> str:
    """The gait a final implies at beta: the core's one definition (`classify_gait`, the
    footfall pattern), "none" for a run with no final. (Until session 14 the campaign named
    finals by Delta31 windows of its own, 1.45-2.45 metachronal, 2.65-3.45 tripod, 3.6-4.8
    retrograde: the tables in docs/studies/gait_campaign3.md were made with those.)"""
    return "none" if final is None else classify_gait(final, beta)


def parse_sets(items: list[str], base: dict[str, Any] | None = None) -> dict[str, Any]:
    out: dict[str, Any] = dict(base or {})
    for it in items:
        k, v = it.split("=", 1)
        out[k] = float(v)
    return out


def finals(
    p: ModelParams,
    betas: list[float],
    starts: list[float],
    *,
    duration: float,
    dt: float | None = None,
    mass_g: float = 3.0,
    slope_deg: float = 0.0,
    nthread: int = 2,
) -> list[dict[str, Any]]:
    specs = [
        RunSpec(
            beta=b,
            d31_init=s,
            duration_s=duration,
            dt_s=dt,
            body_mass_g=mass_g,
            slope_deg=slope_deg,
        )
        for b in betas
        for s in starts
    ]
    rows = [row(r, p) for r in simulate_batch(specs, p, nthread=nthread)]
    for r in rows:
        r["kind"] = kind(r.get("final"), r["beta"])
    return rows


def run_map(args: argparse.Namespace) -> dict[str, Any]:
    base = parse_sets(args.set, STEP_ONE)
    cells = []
    total = len(args.kp_lift) * len(args.com_mm) * len(args.lag_ms)
    for n, (kp, com, lag) in enumerate(
        itertools.product(args.kp_lift, args.com_mm, args.lag_ms), start=1
    ):
        # lag 0: the tracking-error form (feed-forward share 1) at today's kd/kp of 6 ms
        lift = (
            {"kp_lift": kp, "kd_lift": 6e-3 * kp, "velocity_feedforward_lift": 1.0}
            if lag == 0
            else {"kp_lift": kp, "kd_lift": lag * 1e-3 * kp, "velocity_feedforward_lift": 0.0}
        )
        p = ModelParams.of(**{**base, **lift, "com_offset_x": com * 1e-3})
        rows = finals(p, args.betas, args.starts, duration=args.duration, nthread=args.nthread)
        drift, _ = open_loop_drift(
            p,
            betas=args.betas,
            d31s=args.held,
            duration_s=args.ol_duration,
            settle_s=1.0,
            nthread=args.nthread,
        )
        cell = {
            "kp_lift": kp,
            "load_per_stiffness_rel": 5e-3 / kp,
            "com_mm": com,
            "lag_ms": lag,
            "rows": rows,
            "open_loop": {
                str(b): {str(x): float(d) for x, d in zip(args.held, drift[i], strict=True)}
                for i, b in enumerate(args.betas)
            },
        }
        cells.append(cell)
        states = {
            b: sorted(
                {f"{r['kind']}{'' if r.get('settled') else '?'}" for r in rows if r["beta"] == b}
            )
            for b in args.betas
        }
        print(f"[{n}/{total}] kp_lift {kp:g} com {com:+.2f} mm lag {lag} ms: {states}", flush=True)
        if args.out:
            args.out.write_text(
                json.dumps({"base": base, "args": _args_dict(args), "cells": cells})
            )
    return {"base": base, "args": _args_dict(args), "cells": cells}


def _args_dict(args: argparse.Namespace) -> dict[str, Any]:
    return {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()}


def plot_map(data: dict[str, Any], path: Path) -> None:
    """One panel per lift lag: x = centre of mass, y = load per unit lift stiffness; in each
    cell, the states found at beta 0.62 (left half) and 0.70 (right half)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    colours = {
        "tripod": "#d62728",
        "metachronal": "#1f77b4",
        "retrograde": "#2ca02c",
        "other": "#bbbbbb",
        "none": "#000000",
    }
    cells = data["cells"]
    lags = sorted({c["lag_ms"] for c in cells})
    coms = sorted({c["com_mm"] for c in cells})
    loads = sorted({c["load_per_stiffness_rel"] for c in cells})
    betas = data["args"]["betas"]
    fig, axes = plt.subplots(1, len(lags), figsize=(4.2 * len(lags), 3.8), squeeze=False)
    for ax, lag in zip(axes[0], lags, strict=True):
        for c in (c for c in cells if c["lag_ms"] == lag):
            i, j = coms.index(c["com_mm"]), loads.index(c["load_per_stiffness_rel"])
            for bi, b in enumerate(betas):
                found = sorted(
                    {
                        r["kind"]
                        for r in c["rows"]
                        if r["beta"] == b
                        and r.get("slope") is not None
                        and abs(r["slope"]) < MAP_SETTLED
                    }
                )
                found = found or ["other"]
                w = 1.0 / len(betas)
                for k, name in enumerate(found):
                    h = 1.0 / len(found)
                    ax.add_patch(
                        Rectangle(
                            (i - 0.5 + bi * w, j - 0.5 + k * h),
                            w,
                            h,
                            color=colours[name],
                            ec="white",
                            lw=0.5,
                        )
                    )
        for i in range(len(coms)):
            ax.axvline(i, color="white", lw=0.8, ls=":")  # 0.62 left of it, 0.70 right
        for k in range(len(coms) + 1):
            ax.axvline(k - 0.5, color="white", lw=4)
        for k in range(len(loads) + 1):
            ax.axhline(k - 0.5, color="white", lw=4)
        ax.set_xlim(-0.5, len(coms) - 0.5)
        ax.set_ylim(-0.5, len(loads) - 0.5)
        ax.set_xticks(range(len(coms)), [f"{c:+.1f}" for c in coms])
        ax.set_yticks(range(len(loads)), [f"{x:.2f}" for x in loads])
        ax.set_xlabel("centre of mass ahead of the box centre (mm)")
        ax.set_title("lift lag " + ("0 (tracking-error damping)" if lag == 0 else f"{lag} ms"))
    axes[0][0].set_ylabel("load per unit lift stiffness (x default)")
    handles = [Rectangle((0, 0), 1, 1, color=v) for v in colours.values()]
    fig.legend(
        handles,
        [k + (" / unsettled" if k == "other" else "") for k in colours],
        loc="lower center",
        ncol=5,
        frameon=False,
    )
    fig.text(
        0.5,
        0.01,
        f"grey: no run settled (drift >= {MAP_SETTLED} rad per cycle over the "
        "last quarter: a slide through a ghost, or a flat band)",
        ha="center",
        fontsize=8,
    )
    fig.suptitle(
        f"Attractors from starts 1.9 and 3.0 rad; left half of a cell beta {betas[0]}, "
        f"right half beta {betas[-1]}",
        fontsize=10,
    )
    fig.tight_layout(rect=(0, 0.07, 1, 0.95))
    fig.savefig(path, dpi=110)


def table_map(data: dict[str, Any]) -> str:
    betas = data["args"]["betas"]
    lines = [
        "| lift lag (ms) | load / stiffness | COM (mm) | "
        + " | ".join(f"beta {b}: finals from 1.9 / 3.0" for b in betas)
        + " | open-loop drift (mrad/cycle) at "
        + ", ".join(str(x) for x in data["args"]["held"])
        + " |",
        "|---|---|---|" + "---|" * (len(betas) + 1),
    ]
    for c in data["cells"]:
        parts = []
        for b in betas:
            rs = [r for r in c["rows"] if r["beta"] == b]
            parts.append(
                " / ".join(
                    "err"
                    if r.get("error")
                    else f"{r['final']:.2f}{'' if abs(r['slope']) < MAP_SETTLED else '*'}"
                    for r in rs
                )
            )
        ol = "; ".join(
            f"{b}: " + " ".join(f"{1e3 * v:+.1f}" for v in c["open_loop"][str(b)].values())
            for b in betas
        )
        lines.append(
            f"| {c['lag_ms']} | {c['load_per_stiffness_rel']:.2f} | {c['com_mm']:+.2f} | "
            + " | ".join(parts)
            + f" | {ol} |"
        )
    return "\n".join(lines)


def run_robust(args: argparse.Namespace) -> list[dict[str, Any]]:
    base = parse_sets(args.set, STEP_ONE)
    out = []
    for name in args.params:
        for f in (0.9, 1.1):
            p = ModelParams.of(**{**base, name: base[name] * f})
            rows = finals(p, args.betas, args.starts, duration=args.duration, nthread=args.nthread)
            out.append({"param": name, "factor": f, "rows": rows})
            summary = {
                b: [
                    f"{r['final']:.2f}{'' if abs(r['slope']) < MAP_SETTLED else '*'}"
                    for r in rows
                    if r["beta"] == b
                ]
                for b in args.betas
            }
            print(f"{name} x{f}: {summary}", flush=True)
            if args.out:
                args.out.write_text(json.dumps(out))
    return out


def run_sweep(args: argparse.Namespace) -> dict[str, Any]:
    p = ModelParams.of(**parse_sets(args.set, STEP_ONE))
    ramp_s = abs(args.turn - args.start) / args.rate
    spec = RunSpec(beta=args.start, d31_init=args.d31_init, duration_s=1.0, dt_s=args.dt)
    res = sweep(spec, parameter="beta", turn=args.turn, hold_s=args.hold, ramp_s=ramp_s, params=p)
    legs = binned_legs(res.times_s, res.values, res.d31, args.hold, ramp_s)
    return {
        "jumps": {k: crossings(b, args.level) for k, b in legs.items()},
        "rate": args.rate,
        "start": args.start,
        "turn": args.turn,
        "hold_s": args.hold,
        "bins": legs,
        "error": res.error,
    }


SweepJob = tuple[dict[str, Any], float, float, float, float, str]


def _sweep_task(job: SweepJob) -> Task:
    """One triangle sweep as a task: 'up' starts as a tripod (3.0 rad) at `low` and ramps beta
    to `high` and back; 'down' starts as a metachronal gait (1.8 rad) at `high`."""
    sets, low, high, rate, hold, direction = job
    begin, turn, d0 = (low, high, 3.0) if direction == "up" else (high, low, 1.8)
    ramp = Ramp("beta", begin, turn, hold, (high - low) / rate)
    return ramp_task(ramp, RunSpec(beta=begin, d31_init=d0), ModelParams.of(**sets))


def border_sweeps(
    jobs: list[SweepJob], backend: Backend, cache: ResultCache
) -> list[dict[str, Any]]:
    """The sweeps of `jobs` through `sim_core.runs`: each a content-addressed task in `cache`
    (a rerun reads it back, an interrupted campaign resumes) on `backend` (the local pool or a
    Dask cluster), as every `reproduce` run."""
    tasks = [_sweep_task(j) for j in jobs]
    results, _ = run_tasks(tasks, cache, backend, chunk_size=1)
    out = []
    for (sets, _, _, _, hold, direction), t in zip(jobs, tasks, strict=True):
        res = results[t.key]
        assert t.ramp is not None
        out.append({"sets": sets, "direction": direction, "values": res.get("value", []),
                    "d31": res["d31"], "times": res["d31_times_s"], "hold": hold,
                    "ramp_s": t.ramp.ramp_s, "error": res["error"]})  # fmt: skip
    return out


def _backend(args: argparse.Namespace) -> tuple[Backend, ResultCache]:
    return get_backend(args.backend, args.nthread, args.address), ResultCache(args.cache)


def fold_estimates(sw: dict[str, Any], level: float = 2.45, leave: float = 0.15) -> dict[str, Any]:
    """Where a sweep leaves each branch, one estimate per leg of the triangle.

    A leg with beta rising (slowing down) that begins above `level` reports `tripod_dies`: the
    beta of its first touchdown below `level`; a leg with beta falling that begins below
    reports `metachronal_dies`, the first touchdown above. None: the gait never left its
    branch on that leg; absent: the leg began on the other side. Near a fold the gait slides
    slowly, so the crossing lags the fold by a rate-dependent amount; `tripod_leaves` (the
    first of 4 touchdowns `leave` below the tripod's value over the first hold) lags less."""
    t, v, d = (np.asarray(sw[k], dtype=float) for k in ("times", "values", "d31"))
    turn = sw["hold"] + sw["ramp_s"]
    out: dict[str, Any] = {}
    for leg in ((t >= sw["hold"]) & (t < turn), t >= turn):
        vv, dd = v[leg], d[leg]
        if vv.size < 8:
            continue
        rising = vv[-1] > vv[0]
        was_tripod = float(np.median(dd[:4])) > level
        if rising and was_tripod:
            k = next((i for i in range(dd.size) if dd[i] < level), None)
            out["tripod_dies"] = None if k is None else round(float(vv[k]), 4)
            ref = float(np.median(d[t < sw["hold"]])) if sw["direction"] == "up" else dd[0]
            away = (ref - dd) > leave
            j = next((i for i in range(away.size - 3) if away[i : i + 4].all()), None)
            out["tripod_leaves"] = None if j is None else round(float(vv[j]), 4)
        elif not rising and not was_tripod:
            k = next((i for i in range(dd.size) if dd[i] > level), None)
            out["metachronal_dies"] = None if k is None else round(float(vv[k]), 4)
    return out


def run_borders(args: argparse.Namespace) -> list[dict[str, Any]]:
    """How each fold moves with each lever: one triangle sweep per lever value."""
    base = parse_sets(args.set, STEP_ONE)
    jobs: list[tuple[str, float, dict[str, Any]]] = [("base", 0.0, base)]
    for item in args.levers:
        name, values = item.split("=", 1)
        for val in (float(x) for x in values.split(",")):
            jobs.append((name, val, {**base, name: val}))
    out = []
    backend, cache = _backend(args)
    try:
        sweeps = border_sweeps(
            [(j[2], args.low, args.high, args.rate, args.hold, args.direction) for j in jobs],
            backend,
            cache,
        )
    finally:
        backend.close()
    for (name, val, _), sw in zip(jobs, sweeps, strict=True):
        est = fold_estimates(sw)
        out.append({"lever": name, "value": val, **est, "error": sw["error"], "sweep": sw})
        print(f"{name} = {val:g}: " + ", ".join(f"{k} {v}" for k, v in est.items()), flush=True)
        if args.out:
            args.out.write_text(json.dumps(out))
    return out


# The levers the both-folds search may move, each within +-25-50% of the step-one value: the
# border study (gait_campaign3.md, section 3) found each moves the tripod's border by 0.01-0.05
# in beta per 10%.
SEARCH: dict[str, tuple[float, float]] = {
    "com_offset_x": (0.3e-3, 1.5e-3),
    "stand_height": (6.0e-3, 7.0e-3),
    "kp_yaw": (3e-3, 8e-3),
    "swing_height": (0.6e-3, 1.0e-3),
    "swing_shape": (0.8, 1.3),
    "stance_x_hind": (-13.5e-3, -10.5e-3),
    "kd_lift": (2e-6, 5e-6),
    "kp_lift": (2.5e-3, 4e-3),
    "velocity_feedforward_yaw": (0.85, 1.15),
}
PAPER_FOLDS = {"tripod": 0.67, "metachronal": 0.645}


def search_score(est: dict[str, Any], low: float, high: float) -> float:
    """Distance of a sweep's two borders from the paper's (beta units). A tripod that never
    leaves counts as leaving past `high`; a metachronal that never dies, at `low`; where the up
    leg never reached the metachronal, the metachronal border is unknown and scores as `low`."""
    t = est.get("tripod_leaves") or (high + 0.01 if "tripod_dies" in est else low - 0.01)
    m = est.get("metachronal_dies") or low - 0.01
    return abs(t - PAPER_FOLDS["tripod"]) + abs(m - PAPER_FOLDS["metachronal"])


def run_search(args: argparse.Namespace) -> list[dict[str, Any]]:
    """TPE over SEARCH, two sweeps at a time; each trial is one triangle sweep from a tripod."""
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    base = parse_sets(args.set, STEP_ONE)
    study = optuna.create_study(sampler=optuna.samplers.TPESampler(seed=args.seed))
    study.enqueue_trial({k: base.get(k, getattr(ModelParams(), k)) for k in SEARCH})
    out: list[dict[str, Any]] = []
    backend, cache = _backend(args)
    try:
        for _ in range(0, args.trials, backend.workers):
            trials = [study.ask() for _ in range(backend.workers)]
            sets = [{**base, **{k: t.suggest_float(k, *SEARCH[k]) for k in SEARCH}} for t in trials]
            jobs: list[SweepJob] = [(st, args.low, args.high, args.rate, args.hold, "up")
                                    for st in sets]  # fmt: skip
            for t, st, sw in zip(trials, sets, border_sweeps(jobs, backend, cache), strict=True):
                est = fold_estimates(sw) if not sw["error"] else {}
                score = search_score(est, args.low, args.high) if est else 1.0
                study.tell(t, score)
                out.append({"trial": t.number, "score": score, "est": est, "sets": st})
                print(f"trial {t.number}: score {score:.4f} {est}", flush=True)
            if args.out:
                args.out.write_text(json.dumps(out))
    finally:
        backend.close()
    best = min(out, key=lambda r: r["score"])
    print("best:", json.dumps(best))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    f = sub.add_parser("finals")
    f.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.64, 0.655, 0.67, 0.70])
    f.add_argument("--starts", type=float, nargs="+", default=[1.9, 3.0])
    f.add_argument("--duration", type=float, default=30.0)
    f.add_argument("--dt", type=float, default=None)
    f.add_argument("--mass-g", type=float, default=3.0)
    f.add_argument("--slope-deg", type=float, default=0.0)
    m = sub.add_parser("map")
    m.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.70])
    m.add_argument("--starts", type=float, nargs="+", default=[1.9, 3.0])
    m.add_argument("--kp-lift", type=float, nargs="+", default=[5e-3, 4e-3, 3e-3])
    m.add_argument("--com-mm", type=float, nargs="+", default=[0.0, 0.5, 1.0, 1.5])
    m.add_argument("--lag-ms", type=float, nargs="+", default=[0.0, 1.0, 1.5])
    m.add_argument("--held", type=float, nargs="+", default=[2.1, 2.5, 2.9])
    m.add_argument("--duration", type=float, default=20.0)
    m.add_argument("--ol-duration", type=float, default=4.0)
    m.add_argument("--figure", type=Path, default=None)
    r = sub.add_parser("robust")
    r.add_argument(
        "--params", nargs="+", default=list(STEP_ONE.keys() - {"velocity_feedforward_lift"})
    )
    r.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.67, 0.70])
    r.add_argument("--starts", type=float, nargs="+", default=[1.9, 3.0])
    r.add_argument("--duration", type=float, default=25.0)
    s = sub.add_parser("sweep")
    s.add_argument("--start", type=float, default=0.62)
    s.add_argument("--turn", type=float, default=0.70)
    s.add_argument("--d31-init", type=float, default=3.0)
    s.add_argument("--rate", type=float, default=0.002, help="beta per second")
    s.add_argument("--hold", type=float, default=15.0)
    s.add_argument("--level", type=float, default=2.45, help="rad: a crossing is a jump")
    s.add_argument("--dt", type=float, default=None)
    b = sub.add_parser("borders")
    b.add_argument("levers", nargs="*", help="name=v1,v2,... (each value one sweep)")
    b.add_argument("--low", type=float, default=0.60)
    b.add_argument("--high", type=float, default=0.72)
    b.add_argument("--rate", type=float, default=0.002, help="beta per second")
    b.add_argument("--hold", type=float, default=10.0)
    b.add_argument("--direction", choices=["up", "down"], default="up")
    q = sub.add_parser("search")
    q.add_argument("--trials", type=int, default=60)
    q.add_argument("--seed", type=int, default=0)
    q.add_argument("--low", type=float, default=0.60)
    q.add_argument("--high", type=float, default=0.72)
    q.add_argument("--rate", type=float, default=0.004, help="beta per second")
    q.add_argument("--hold", type=float, default=8.0)
    pm = sub.add_parser("plotmap", help="table and figure again from a map's JSON")
    pm.add_argument("json", type=Path)
    pm.add_argument("--figure", type=Path, required=True)
    for x in (b, q):  # sweeps through sim_core.runs: cached, on the local pool or Dask
        x.add_argument("--backend", choices=["local", "dask", "inline"], default="local")
        x.add_argument("--address", default=None, help="dask scheduler, e.g. tcp://host:8786")
        x.add_argument("--cache", type=Path, default=default_cache_dir())
    for x in (f, m, r, s, b, q):
        x.add_argument("--set", nargs="*", default=[], help="name=value over STEP_ONE")
        x.add_argument("--nthread", type=int, default=2)
        x.add_argument("--out", type=Path, default=None, help="JSON file for the raw rows")
    args = ap.parse_args(argv)
    data: Any
    if args.cmd == "plotmap":
        data = json.loads(args.json.read_text())
        print(table_map(data))
        plot_map(data, args.figure)
        return 0
    if args.cmd == "finals":
        p = ModelParams.of(**parse_sets(args.set, STEP_ONE))
        rows = finals(
            p,
            args.betas,
            args.starts,
            duration=args.duration,
            dt=args.dt,
            mass_g=args.mass_g,
            slope_deg=args.slope_deg,
            nthread=args.nthread,
        )
        print(table_finals(rows))
        for rw in rows:
            print(
                f"  beta {rw['beta']} start {rw['start']}: "
                + (
                    "error"
                    if rw.get("error")
                    else f"{rw['final']:.3f} (drift {rw['slope']:+.4f}/cycle, {rw['kind']})"
                )
            )
        data = rows
    elif args.cmd == "map":
        data = run_map(args)
        print(table_map(data))
        if args.figure:
            plot_map(data, args.figure)
    elif args.cmd == "robust":
        data = run_robust(args)
    elif args.cmd == "borders":
        data = run_borders(args)
    elif args.cmd == "search":
        data = run_search(args)
    else:
        data = run_sweep(args)
        print(json.dumps({k: v for k, v in data.items() if k != "bins"}, indent=1))
        for leg, bins in data["bins"].items():
            print(leg, " ".join(f"{k}:{v:.2f}" for k, v in bins.items()))
    if args.out:
        args.out.write_text(json.dumps(data))
    return 0


if __name__ == "__main__":
    sys.exit(main())

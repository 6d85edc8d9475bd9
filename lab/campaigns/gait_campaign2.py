"""Gait selection, second campaign (issue 18): lead 1 reproduced inside the project.

Sub-commands (numbers and the commands that made them: docs/studies/gait_campaign2.md):

    finals  fixed-beta runs from many starts: final Delta31, settled?, landing share, speed, slip
    sweep   the paper's down/up beta sweep (Fig. 6a) with `sim_core.sweep`, binned per 0.005
    openloop  phase resetting off, Delta31 held on a grid: mean jump e_i per leg and the drift
            1/4[(e5+e6)-(e1+e2)] it would give (a return map's driving term)

Parameter sets are the lead-1 point (`LEAD1`) plus `--set name=value` overrides. Nothing here
knows the target gait; beta enters only through the paper's eq. 2 (inside sim_core).

    python -m lab.campaigns.gait_campaign2 finals --betas 0.62 0.70 --duration 20
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from sim_core import ModelParams, RunResult, RunSpec, nominal_speed, simulate_batch, sweep
from sim_core.contract import TAIL_DRIFT_SETTLED, circular_mean, settling
from sim_core.research import angle_diff, phi_aep

LEAD1: dict[str, Any] = {
    "velocity_feedforward_yaw": 0.0,  # was pd_damping="joint_velocity"
    "velocity_feedforward_lift": 0.0,
    "kp_lift": 5e-3,  # the defaults of the time, now set explicitly
    "stand_height": 7e-3,
    "kd_yaw": 1e-5,
    "kd_lift": 1e-5,
    "com_offset_x": 1e-3,
}
EIGHT = [round(2 * math.pi * k / 8, 4) for k in range(8)]
EXTRA = [1.6, 2.2, 2.6, 3.0, 3.6]
SETTLE_SLOPE = TAIL_DRIFT_SETTLED  # rad per gait cycle over the last quarter: below it, settled
CLUSTER_TOL = 0.08  # rad: finals closer than this count as one attractor


def parse_sets(items: list[str]) -> dict[str, Any]:
    out: dict[str, Any] = dict(LEAD1)
    for it in items:
        k, v = it.split("=", 1)
        try:
            out[k] = float(v)
        except ValueError:
            out[k] = v
    return out


def tail_stats(r: RunResult) -> dict[str, Any]:
    """Final Delta31, its drift per gait cycle over the last quarter and THE settled rule
    (`gait.settling`; this campaign's own rule, |drift| < SETTLE_SLOPE, is the rule's core)."""
    s = settling(r.events.d31)
    if s.final is None:
        return {"final": None, "slope": None, "settled": False}
    return {"final": s.final, "slope": s.drift, "settled": s.settled}


def row(r: RunResult, p: ModelParams) -> dict[str, Any]:
    s = r.spec
    out: dict[str, Any] = {"beta": s.beta, "start": s.d31_init, "dt": r.dt_s, "error": r.error}
    if r.error:
        return out
    out.update(tail_stats(r))
    v0 = nominal_speed(s.beta, p.trajectory.stroke, p.trajectory.swing_duration) * 100
    out["speed_rel"] = None if r.measures.speed_cm_s is None else r.measures.speed_cm_s / v0 - 1
    out["landing"] = r.measures.landing_swing_share
    out["slip"] = r.measures.slip_fraction
    return out


def clusters(finals: list[float]) -> list[tuple[float, float, int]]:
    """(lo, hi, count) groups of finals on the circle, sorted by value."""
    vals = sorted(finals)
    groups: list[list[float]] = []
    for v in vals:
        if groups and abs(float(angle_diff(v, groups[-1][-1]))) < CLUSTER_TOL:
            groups[-1].append(v)
        else:
            groups.append([v])
    if len(groups) > 1 and abs(float(angle_diff(groups[0][0], groups[-1][-1]))) < CLUSTER_TOL:
        groups[0] = groups.pop() + groups[0]
    return [(g[0], g[-1], len(g)) for g in groups]


def fmt_cluster(c: tuple[float, float, int]) -> str:
    lo, hi, n = c
    v = f"{lo:.2f}" if abs(hi - lo) < 0.005 else f"{lo:.2f}-{hi:.2f}"
    return f"{v} x{n}"


def run_finals(args: argparse.Namespace) -> list[dict[str, Any]]:
    sets = parse_sets(args.set)
    p = ModelParams.of(**sets)
    starts = args.starts or (EIGHT + (EXTRA if args.extra else []))
    specs = [
        RunSpec(beta=b, d31_init=s, duration_s=args.duration, dt_s=args.dt)
        for b in args.betas
        for s in starts
    ]
    res = simulate_batch(specs, p, nthread=args.nthread)
    rows = [row(r, p) for r in res]
    if args.diag:
        for r, rw in zip(res, rows, strict=True):
            if not r.error:
                rw["diag"] = diagnose(r)
    return rows


def diagnose(r: RunResult) -> dict[str, Any]:
    """Over the last quarter: mean phase jump e_i = phi_AEP - phi_touchdown per leg (> 0 =
    landed early), the predicted drift 1/4[(e5+e6)-(e1+e2)], and the mean touchdown delay of
    each hind leg after its diagonal fore leg's touchdown and before that fore leg's lift-off."""
    aep = phi_aep(r.spec.beta)
    t_end = float(r.events.d31_times_s[-1]) if r.events.d31_times_s.size else 0.0
    t0 = t_end * 0.75
    e = []
    for td, ph in zip(r.events.touchdowns_s, r.events.touchdown_phases, strict=True):
        m = td > t0
        e.append(float(np.mean(angle_diff(aep, ph[m]))) if m.any() else float("nan"))
    drift = 0.25 * ((e[4] + e[5]) - (e[0] + e[1]))
    # paper order: 1 = left fore, 2 = right fore, 3/4 middle, 5 = left hind, 6 = right hind;
    # diagonal of hind 5 (left) is fore 2 (right), of hind 6 is fore 1
    delays = {}
    for hind, fore in ((4, 1), (5, 0)):
        th = r.events.touchdowns_s[hind][r.events.touchdowns_s[hind] > t0]
        tf = r.events.touchdowns_s[fore]
        lf = r.events.liftoffs_s[fore]
        after_td, before_lo = [], []
        for t in th:
            prev = tf[tf <= t]
            nxt = lf[lf >= t]
            if prev.size:
                after_td.append(t - prev[-1])
            if nxt.size:
                before_lo.append(nxt[0] - t)
        delays[f"hind{hind + 1}_after_fore{fore + 1}_td_ms"] = 1e3 * float(np.mean(after_td))
        delays[f"hind{hind + 1}_before_fore{fore + 1}_lo_ms"] = 1e3 * float(np.mean(before_lo))
    return {"e": e, "drift_pred": drift, **delays}


def run_openloop(args: argparse.Namespace) -> list[dict[str, Any]]:
    sets = parse_sets(args.set)
    p = ModelParams.of(**sets)
    grid = [round(x, 4) for x in np.arange(args.lo, args.hi + 1e-9, args.step)]
    specs = [
        RunSpec(beta=b, d31_init=x, duration_s=args.duration, phase_reset=False, dt_s=args.dt)
        for b in args.betas
        for x in grid
    ]
    res = simulate_batch(specs, p, nthread=args.nthread)
    out = []
    for r in res:
        if r.error:
            out.append({"beta": r.spec.beta, "d31": r.spec.d31_init, "error": r.error})
            continue
        aep = phi_aep(r.spec.beta)
        e = []
        for td, ph in zip(r.events.touchdowns_s, r.events.touchdown_phases, strict=True):
            m = td > args.duration / 3
            e.append(float(np.mean(angle_diff(aep, ph[m]))) if m.any() else float("nan"))
        fore, hind = (e[0] + e[1]) / 2, (e[4] + e[5]) / 2
        out.append(
            {
                "beta": r.spec.beta,
                "d31": r.spec.d31_init,
                "e": e,
                "e_fore": fore,
                "e_mid": (e[2] + e[3]) / 2,
                "e_hind": hind,
                "drift": 0.5 * (hind - fore),
                "landing": r.measures.landing_swing_share,
            }
        )
    return out


def table_openloop(rows: list[dict[str, Any]]) -> str:
    lines = [
        "| beta | Delta31 held | e_fore | e_mid | e_hind | drift/cycle 1/2(e_h - e_f) |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r.get("error"):
            lines.append(f"| {r['beta']} | {r['d31']:.2f} | error | | | |")
            continue
        lines.append(
            f"| {r['beta']} | {r['d31']:.2f} | {r['e_fore']:+.3f} | {r['e_mid']:+.3f} | "
            f"{r['e_hind']:+.3f} | {r['drift']:+.4f} |"
        )
    return "\n".join(lines)


def table_finals(rows: list[dict[str, Any]]) -> str:
    lines = [
        "| beta | attractors (final x starts) | unsettled (start: final, slope) | landing | "
        "speed vs eq. 2 | slip | errors |",
        "|---|---|---|---|---|---|---|",
    ]
    for b in sorted({r["beta"] for r in rows}):
        rs = [r for r in rows if r["beta"] == b]
        ok = [r for r in rs if not r["error"] and r.get("final") is not None]
        errs = len(rs) - len(ok)
        settled = [r for r in ok if r["settled"]]
        uns = [r for r in ok if not r["settled"]]
        cl = ", ".join(fmt_cluster(c) for c in clusters([r["final"] for r in settled]))
        un = "; ".join(f"{r['start']:.2f}: {r['final']:.2f}, {r['slope']:+.4f}" for r in uns)

        def rng(key: str, scale: float = 1.0, fmtx: str = "{:.2f}", ok: list = ok) -> str:
            v = [r[key] * scale for r in ok if r.get(key) is not None]
            return (fmtx.format(min(v)) + " to " + fmtx.format(max(v))) if v else "-"

        lines.append(
            f"| {b} | {cl or '-'} | {un or '-'} | {rng('landing')} | "
            f"{rng('speed_rel', 100, '{:+.1f}')} % | {rng('slip', 100, '{:.1f}')} % | {errs} |"
        )
    return "\n".join(lines)


JUMP_LEVEL = 2.3  # rad, between the metachronal (~2.05) and tripod-side (~2.54) branches


def crossings(bins: dict[str, float], level: float = JUMP_LEVEL) -> list[float]:
    """Beta values where the binned Delta31 crosses `level` (linear between bins): the
    sweep's jumps. `sweep_summary` finds none here because its tripod window starts at 2.54,
    the very value of this setting's tripod-side branch."""
    keys = sorted(bins, key=float)
    out = []
    for a, b in itertools.pairwise(keys):
        da, db = bins[a] - level, bins[b] - level
        if da * db < 0:
            out.append(round(float(a) + (float(b) - float(a)) * da / (da - db), 4))
    return out


def binned_legs(
    times: list[float], values: list[float], d31: list[float], hold: float, ramp_s: float
) -> dict[str, dict[str, float]]:
    """Delta31 of each leg of a triangle sweep, circular mean per 0.005 of the swept value."""
    t, v, d = (np.asarray(x) for x in (times, values, d31))
    legs = {}
    for name, (a, b) in {
        "first": (hold, hold + ramp_s),
        "second": (hold + ramp_s, hold + 2 * ramp_s),
    }.items():
        m = (t >= a) & (t < b)
        bins: dict[float, list[float]] = {}
        for vi, di in zip(v[m], d[m], strict=True):
            bins.setdefault(round(round(vi / 0.005) * 0.005, 3), []).append(di)
        legs[name] = {str(k): circular_mean(x) for k, x in sorted(bins.items())}
    return legs


def run_sweep(args: argparse.Namespace) -> dict[str, Any]:
    sets = parse_sets(args.set)
    p = ModelParams.of(**sets)
    ramp_s = abs(args.turn - args.start) / args.rate
    spec = RunSpec(beta=args.start, d31_init=args.d31_init, duration_s=1.0, dt_s=args.dt)
    res = sweep(spec, parameter="beta", turn=args.turn, hold_s=args.hold, ramp_s=ramp_s, params=p)
    legs = binned_legs(res.times_s, res.values, res.d31, args.hold, ramp_s)
    return {
        "jumps": {k: crossings(b) for k, b in legs.items()},
        "start": args.start,
        "turn": args.turn,
        "rate": args.rate,
        "ramp_s": ramp_s,
        "hold_s": args.hold,
        "summary": res.summary,
        "error": res.error,
        "bins": legs,
        "series": {"t": list(res.times_s), "beta": list(res.values), "d31": list(res.d31)},
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    f = sub.add_parser("finals")
    f.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.64, 0.655, 0.67, 0.685, 0.70])
    f.add_argument("--starts", type=float, nargs="*", default=None)
    f.add_argument("--extra", action="store_true", help="add starts 1.6 2.2 2.6 3.0 3.6")
    f.add_argument("--duration", type=float, default=20.0)
    f.add_argument("--dt", type=float, default=None)
    f.add_argument("--diag", action="store_true")
    o = sub.add_parser("openloop")
    o.add_argument("--betas", type=float, nargs="+", default=[0.62, 0.70])
    o.add_argument("--lo", type=float, default=1.6)
    o.add_argument("--hi", type=float, default=3.4)
    o.add_argument("--step", type=float, default=0.15)
    o.add_argument("--duration", type=float, default=3.0)
    o.add_argument("--dt", type=float, default=None)
    s = sub.add_parser("sweep")
    s.add_argument("--start", type=float, default=0.70)
    s.add_argument("--turn", type=float, default=0.62)
    s.add_argument("--d31-init", type=float, default=1.9)
    s.add_argument("--rate", type=float, default=0.002, help="beta per second")
    s.add_argument("--hold", type=float, default=15.0)
    s.add_argument("--dt", type=float, default=None)
    for x in (f, s, o):
        x.add_argument("--set", nargs="*", default=[], help="name=value over LEAD1")
        x.add_argument("--nthread", type=int, default=2)
        x.add_argument("--out", type=Path, default=None, help="JSON file for the raw rows")
    args = ap.parse_args(argv)
    if args.cmd == "finals":
        rows = run_finals(args)
        print(table_finals(rows))
        for r in rows:
            print(json.dumps(r))
        data: Any = rows
    elif args.cmd == "openloop":
        data = run_openloop(args)
        print(table_openloop(data))
    else:
        data = run_sweep(args)
        print(json.dumps({k: v for k, v in data.items() if k != "series"}, indent=1))
    if args.out:
        args.out.write_text(json.dumps(data))
    return 0


if __name__ == "__main__":
    sys.exit(main())

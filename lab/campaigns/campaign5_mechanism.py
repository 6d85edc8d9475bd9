"""Fifth campaign, point 1 (issue 40): which legs' landings make the drift surface, and does the
fore legs' response near L_FH have the sign and timing a response-time reading needs?

    python -m lab.campaigns.campaign5_mechanism [--out out/campaign5]

Three measurements, every probe through `sim_core.runs` (cached, resumable):
1. Per-leg jumps on both grounds at beta 0.62, 0.645, 0.70 (D 1.5-3.3 by 0.05, 0.5 s + 2 s):
   the drift d = 1/4 [(e5 + e6) - (e1 + e2)] split into its hind part (e5 + e6) / 4 and its
   fore part -(e1 + e2) / 4, over the 2.1-2.9 band and at each stable zero (value and slope).
2. The fore legs' mean jump (e1 + e2) / 2 against the time from the ipsilateral hind leg's
   lift-off to the fore landing: with Delta31 = Delta53 = D, Delta51 = 2 D, so at a fore
   touchdown (phi1 = phi_AEP) the hind has been in swing for 2 (D - pi beta) / omega, omega =
   2 pi (1 - beta) / T_sw: positive = the fore lands after the hind lifted (D > L_FH).
3. T_sw 30 / 34 / 38 ms at fixed joint time constants (a test, not adopted): drift surfaces
   over beta 0.595-0.64 by 0.0025 (the protocol of Fig. 8): where the metachronal branch
   (1.7-1.9) and the tripod branch (2.8-3.0) end.
Writes `mechanism5.json` under --out and prints the tables quoted in docs/studies/journal.md.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from sim_core import ModelParams, ResultCache, default_cache_dir, drift_surface, get_backend
from sim_core.contract import DriftSurface, SurfaceConfig, surface_grid

JUMP_BETAS = (0.62, 0.645, 0.70)
JUMP_CONFIG = SurfaceConfig(d31_grid=surface_grid(1.5, 3.3, 0.05), average_s=2.0)
BAND = (2.1, 2.9)  # the band the issue reads at -3 to -5 mrad per cycle
TSW_MS = (30.0, 34.0, 38.0)
FOLD_BETAS = surface_grid(0.595, 0.64, 0.0025)
METACHRONAL = (1.6, 2.0)  # where the metachronal branch's stable zero lives
TRIPOD = (2.8, 3.05)


def _parts(surface: DriftSurface, beta: float) -> list[dict[str, float]]:
    """Per usable probe: D, sampled Delta31, drift, its hind and fore parts, fore mean jump."""
    rows = []
    for p in surface.curve_at(beta):
        e = np.array([np.nan if x is None else x for x in p.jumps], dtype=float)
        rows.append({"d": p.pin_d31, "d31": float(p.d31 or 0.0), "drift": float(p.drift or 0.0),
                     "hind": float(e[4] + e[5]) / 4, "fore": -float(e[0] + e[1]) / 4,
                     "e_fore": float(e[0] + e[1]) / 2, "e_hind": float(e[4] + e[5]) / 2,
                     "e_mid": float(e[2] + e[3]) / 2})  # fmt: skip
    return rows


def after_hind_liftoff_ms(d: float, beta: float, swing_s: float) -> float:
    """Time from the ipsilateral hind lift-off to the fore landing at Delta31 = Delta53 = d."""
    omega = 2 * math.pi * (1 - beta) / swing_s
    return 1e3 * 2 * (d - math.pi * beta) / omega


def jump_reading(surface: DriftSurface, beta: float) -> dict[str, Any]:
    rows = _parts(surface, beta)
    band = [r for r in rows if BAND[0] <= r["d31"] <= BAND[1]]
    zeros = []
    for z in surface.zeros_at(beta):
        near = sorted(rows, key=lambda r: abs(r["d31"] - z.d31))[:2]
        lo, hi = sorted(near, key=lambda r: r["d31"])
        dx = hi["d31"] - lo["d31"]
        zeros.append({
            "d31": z.d31, "stable": z.stable,
            "hind": 0.5 * (lo["hind"] + hi["hind"]), "fore": 0.5 * (lo["fore"] + hi["fore"]),
            "slope_hind": (hi["hind"] - lo["hind"]) / dx if dx > 0 else None,
            "slope_fore": (hi["fore"] - lo["fore"]) / dx if dx > 0 else None,
        })  # fmt: skip
    return {
        "beta": beta,
        "band_drift": float(np.mean([r["drift"] for r in band])) if band else None,
        "band_hind": float(np.mean([r["hind"] for r in band])) if band else None,
        "band_fore": float(np.mean([r["fore"] for r in band])) if band else None,
        "zeros": zeros,
        "rows": rows,
    }


def fore_response(rows: list[dict[str, float]], beta: float, swing_s: float) -> list[list[float]]:
    """(ms after the hind lift-off, fore mean jump in mrad) within 0.5 rad of L_FH."""
    lfh = math.pi * beta
    return [[round(after_hind_liftoff_ms(r["d"], beta, swing_s), 2), round(1e3 * r["e_fore"], 1)]
            for r in rows if abs(r["d"] - lfh) <= 0.5]  # fmt: skip


def branch_end(surface: DriftSurface, window: tuple[float, float]) -> dict[str, Any]:
    """The betas with a stable zero inside `window`, and where that run of betas ends."""
    have = [
        b
        for b in surface.betas
        if any(z.stable and window[0] <= z.d31 <= window[1] for z in surface.zeros_at(b))
    ]
    return {"betas": have, "lowest": min(have, default=None), "highest": max(have, default=None)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/campaign5")
    ap.add_argument("--cache", default=str(default_cache_dir()))
    ap.add_argument("--workers", type=int, default=2)
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    backend, cache = get_backend("local", a.workers), ResultCache(a.cache)
    report: dict[str, Any] = {"jumps": {}, "tsw": {}}
    t0 = time.perf_counter()
    for ground in ("constraint", "penalty"):
        p = ModelParams.of(ground=ground)
        sf = drift_surface(JUMP_BETAS, cache=cache, backend=backend, config=JUMP_CONFIG,
                           params=p, refine=False, progress=False)  # fmt: skip
        readings = [jump_reading(sf, b) for b in JUMP_BETAS]
        for r in readings:
            r["fore_response"] = fore_response(r["rows"], r["beta"], p.trajectory.swing_duration)
        report["jumps"][ground] = readings
        print(f"\n{ground} ground ({time.perf_counter() - t0:.0f} s)")
        for r in readings:
            print(
                f" beta {r['beta']}: band {BAND} drift {1e3 * (r['band_drift'] or 0):+.2f} = hind "
                f"{1e3 * (r['band_hind'] or 0):+.2f} + fore {1e3 * (r['band_fore'] or 0):+.2f} mrad"
            )
            for z in r["zeros"]:
                print(
                    f"   zero {z['d31']:.3f} {'S' if z['stable'] else 'U'}: hind "
                    f"{1e3 * z['hind']:+.1f} fore {1e3 * z['fore']:+.1f} mrad; slope hind "
                    f"{1e3 * (z['slope_hind'] or 0):+.1f} fore {1e3 * (z['slope_fore'] or 0):+.1f}"
                    " mrad/rad"
                )
            print(f"   fore response (ms after hind lift-off, mrad): {r['fore_response']}")
    for tsw in TSW_MS:
        p = ModelParams.of(swing_duration=tsw * 1e-3)
        sf = drift_surface(FOLD_BETAS, cache=cache, backend=backend, config=SurfaceConfig(),
                           params=p, progress=False)  # fmt: skip
        report["tsw"][str(tsw)] = {
            "metachronal": branch_end(sf, METACHRONAL),
            "tripod": branch_end(sf, TRIPOD),
            "folds": [f.model_dump() for f in sf.folds],
            "zeros": [z.model_dump() for z in sf.zeros],
            "sim_s": sf.sim_s,
        }
        m, t = report["tsw"][str(tsw)]["metachronal"], report["tsw"][str(tsw)]["tripod"]
        print(
            f"\nT_sw {tsw} ms ({time.perf_counter() - t0:.0f} s): metachronal stable zero at "
            f"beta >= {m['lowest']}; tripod at beta <= {t['highest']} (betas {t['betas']})"
        )
    report["wall_s"] = time.perf_counter() - t0
    (out / "mechanism5.json").write_text(json.dumps(report))
    print(f"\n{report['wall_s']:.0f} s; wrote {out / 'mechanism5.json'}")


if __name__ == "__main__":
    main()

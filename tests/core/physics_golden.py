"""The physics' numbers, dumped: what `PHYSICS_VERSION` promises stays the same.

The result cache keys a run by its spec, its non-default parameters and `PHYSICS_VERSION`, not
by the bytes of the physics sources (a comment or a rename then keeps every cached run). The
price is a promise: a change that moves a simulated number bumps the version. This dump holds
the promise to account. It covers every way a number is made: both grounds, a run that fails,
one that stops once settled, a pinned drift-surface probe, a ramp, and the live `Simulation`;
`test_physics_version` compares a fresh dump with the committed one (`physics_golden.json`).

Regenerate after a deliberate physics change (and bump the version in the same commit):
    .venv/bin/python -m tests.core.physics_golden --write
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from sim_core.model.live import Simulation
from sim_core.model.params import ModelParams
from sim_core.model.ramp import Ramp
from sim_core.model.spec import RunSpec
from sim_core.runs.tasks import Task, execute_chunk, ramp_task, run_task

GOLDEN_FILE = Path(__file__).with_name("physics_golden.json")
# A deliberate physics change moves these numbers by far more than this; a different CPU or
# BLAS build (ulp-level differences, grown by a short walk) by far less.
REL_TOL = 1e-9


def _cases() -> dict[str, Task]:
    penalty = ModelParams.of(ground="penalty")
    walk = RunSpec(beta=0.66, d31_init=2.094, duration_s=0.6)
    return {
        "constraint": run_task(walk),
        "penalty": run_task(walk, penalty),
        "failed": run_task(RunSpec(slope_deg=60.0, duration_s=0.6)),
        # settled by 20 s (>= 160 touchdowns: `gait.SETTLED_MIN_TAIL`) and stops there
        "settled_stop": run_task(
            RunSpec(beta=0.70, d31_init=1.69, duration_s=30.0, stop_if_settled_s=20.0)
        ),
        "pinned": run_task(RunSpec(beta=0.655, d31_init=2.3, pin_d31=2.3, duration_s=1.0)),
        "ramp": ramp_task(Ramp("beta", 0.66, 0.62, 0.1, 0.2), RunSpec(d31_init=2.094)),
        "dt_half": run_task(walk.model_copy(update={"dt_s": 2.5e-5})),
    }


def _live() -> dict[str, Any]:
    sim = Simulation(RunSpec(beta=0.66, d31_init=2.094))
    sim.advance(0.3)
    sim.set_beta(0.63)
    sim.advance(0.2)
    return {
        "time_s": sim.time_s,
        "qpos": sim.data.qpos.tolist(),
        "phases": np.asarray(sim.phases).tolist(),
        "d31_events": [list(e) for e in sim.d31_events],
    }


def dump() -> dict[str, Any]:
    """Every case's result (without its wall-clock cost), grouped as `execute_chunk` needs."""
    cases = _cases()
    out: dict[str, Any] = {}
    groups: dict[Any, list[str]] = {}
    for name, task in cases.items():
        groups.setdefault(task.group(), []).append(name)
    for names in groups.values():
        for name, res in zip(names, execute_chunk([cases[n] for n in names]), strict=True):
            res.pop("compute_s", None)
            out[name] = res
    out["live"] = _live()
    return out


def differences(a: Any, b: Any, path: str = "", tol: float = REL_TOL) -> list[str]:
    """Where two dumps differ (beyond `tol` relative for floats), as readable paths."""
    if isinstance(a, dict) and isinstance(b, dict):
        diffs = [f"{path}/{k}: only in one" for k in set(a) ^ set(b)]
        for k in sorted(set(a) & set(b)):
            diffs += differences(a[k], b[k], f"{path}/{k}", tol)
        return diffs
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} != {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b, strict=True))
                for d in differences(x, y, f"{path}[{i}]", tol)]  # fmt: skip
    if isinstance(a, float) and isinstance(b, float):
        ok = math.isclose(a, b, rel_tol=tol, abs_tol=1e-300)
        return [] if ok else [f"{path}: {a!r} != {b!r}"]
    return [] if a == b else [f"{path}: {a!r} != {b!r}"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="write physics_golden.json")
    parser.add_argument("--version", required=True, help="the physics version these belong to")
    args = parser.parse_args()
    data = {"version": args.version, "dump": dump()}
    if args.write:
        GOLDEN_FILE.write_text(json.dumps(data, indent=0, allow_nan=True) + "\n")
    print(json.dumps({k: sorted(v) for k, v in data["dump"].items()}, indent=1)[:2000])


if __name__ == "__main__":
    main()

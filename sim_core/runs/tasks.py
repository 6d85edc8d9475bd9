"""Experiments as small pure tasks: a frozen description in, a JSON-serialisable result out.

A `Task` is everything one simulation needs (its `RunSpec`, an optional live ramp of beta, body
mass or slope, the `ModelParams` and the physics' version) as plain strings, so it is hashable,
picklable to any worker, and has a stable content hash (`Task.key`). The hash names the task's
cache file (`sim_core.runs.cache`): a changed parameter, spec or `PHYSICS_VERSION` gives a new
key, so a stale result is never reused, and an unchanged one is never recomputed. The spec and
parameters are stored without their default values, so a new field whose default keeps the
physics (and a comment or rename in the sources) keeps every key; changing a default moves the
numbers, which bumps the version (`sim_core.model.version`). The parameters enter the key as a
flat mapping of leaf names (`params_json`): however `ModelParams` groups its fields (a
`body`, a `ground` ...), a parameter's key part is its own name and value, so regrouping the
model keeps every key.

`execute_chunk` runs a list of compatible tasks (same parameters and numerics) as one
`BatchRunner` batch on one thread. Batching several simulations in one runner amortises the
per-control-period Python and controller overhead (measured: 4 simulations stepped together cost
0.38 s of wall time per simulated second each, against 0.52 s alone), and each simulation in a
batch evolves exactly as it would alone, so how tasks are grouped never changes a number.
"""

from __future__ import annotations

import hashlib
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from sim_core.model.gait import yaw_of
from sim_core.model.params import ModelParams
from sim_core.model.ramp import RAMP_PARAMS, Ramp, RampDriver
from sim_core.model.runner import BatchRunner
from sim_core.model.spec import RunSpec
from sim_core.model.version import PHYSICS_VERSION
from sim_core.runs.keys import canonical as _canonical
from sim_core.runs.keys import params_hash as params_hash  # the keys' parts: runs/keys.py
from sim_core.runs.keys import params_json as params_json
from sim_core.runs.keys import spec_json as spec_json

# Bump when what a task computes or returns changes; old cache entries then stop matching.
TASK_VERSION = 1


@dataclass(frozen=True)
class Task:
    """One simulation, described by strings only (hashable, picklable, content-addressed)."""

    spec: str  # RunSpec's non-default fields as canonical JSON
    params: str  # ModelParams' non-default fields as canonical JSON
    ramp: Ramp | None = None
    physics: str = PHYSICS_VERSION
    version: int = TASK_VERSION

    @property
    def kind(self) -> str:
        return "run" if self.ramp is None else "ramp"

    @property
    def key(self) -> str:
        """sha256 (24 hex) of the whole description: the cache file's name."""
        return hashlib.sha256(_canonical(asdict(self)).encode()).hexdigest()[:24]

    def run_spec(self) -> RunSpec:
        return RunSpec.model_validate_json(self.spec)

    def model_params(self) -> ModelParams:
        return ModelParams.model_validate_json(self.params)

    @property
    def duration_s(self) -> float:
        return self.run_spec().duration_s

    def group(self) -> tuple[str, str, str | None, float | None, float | None]:
        """Tasks with the same group can share one batch (same model and numerics)."""
        s = self.run_spec()
        return (self.params, self.physics, s.integrator, s.dt_s, s.control_dt_s)


def run_task(spec: RunSpec, params: ModelParams | None = None) -> Task:
    """A plain run of `spec` (fixed beta, mass and slope)."""
    return Task(
        spec=spec_json(spec),
        params=params_json(params),
    )


def ramp_task(ramp: Ramp, spec: RunSpec, params: ModelParams | None = None) -> Task:
    """A run whose `ramp.param` follows the triangle `ramp`, starting from `spec`."""
    if ramp.param not in RAMP_PARAMS:
        raise ValueError(f"cannot ramp {ramp.param!r}; choose from {RAMP_PARAMS}")
    start = spec.model_copy(update={ramp.param: ramp.start, "duration_s": ramp.duration_s})
    RunSpec.model_validate(start.model_dump() | {ramp.param: ramp.turn})  # both ends valid
    return Task(
        spec=spec_json(start),
        params=params_json(params),
        ramp=ramp,
    )


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def execute_chunk(
    tasks: Sequence[Task], progress: Callable[[float], None] | None = None, *, nthread: int = 1
) -> list[dict[str, Any]]:
    """Run compatible tasks as one batch; one JSON-able dict per task: the run's summary
    (`RunResult.summary`, read back by `summary_of`) plus `EXTRA_KEYS`.

    progress, if given, is called with the share of the chunk's simulated time done (0..1),
    about every 1% (`BatchRunner.run`).

    Single-threaded by default, on purpose: parallelism comes from running many chunks at once
    (a process pool or cluster workers), which also parallelises the controller, not only the
    physics. `nthread` > 1 steps the batch's physics on that many threads: for a caller that
    runs its chunks one after another in a process given several cores (a service worker);
    each simulation steps alone on its thread, so the numbers are the same.
    """
    if not tasks:
        return []
    if len({t.group() for t in tasks}) != 1:
        raise ValueError("a chunk needs one parameter set and one numerics; group the tasks")
    specs = [t.run_spec() for t in tasks]
    params = tasks[0].model_params()
    t0 = time.perf_counter()
    # always recorded, so that a result never depends on which tasks share its batch
    runner = BatchRunner(specs, params, nthread=nthread, record=True)
    ramps = [(i, t.ramp) for i, t in enumerate(tasks) if t.ramp is not None]
    set_ramps = RampDriver(ramps, runner.control_dt)
    set_ramps(runner)  # the values of the first period
    runner.run(progress, hook=set_ramps if ramps else None)
    share = (time.perf_counter() - t0) / len(tasks)
    out = []
    for i, task in enumerate(tasks):
        res = runner.result(i)
        ev, ser = res.events, res.series
        # the run's summary (every measure, generated from its fields), its touchdown times,
        # the compute it cost; a non-finite float is stored as null (JSON has no NaN)
        item: dict[str, Any] = {
            k: _finite(v) if isinstance(v, float) else v for k, v in res.summary().items()
        }
        item |= {"d31_times_s": ev.d31_times_s.tolist(), "compute_s": share}
        if specs[i].pin_d31 is not None:
            # a drift-surface probe (`sim_core.paper.surface`): its touchdowns and the phase
            # at each before eq. 4, from which the per-leg jumps and the drift are read (its
            # Delta31 samples are the summary's d31)
            item["touchdowns_s"] = [t.tolist() for t in ev.touchdowns_s]
            item["touchdown_phases"] = [p.tolist() for p in ev.touchdown_phases]
        if task.ramp is not None:
            item["value"] = [float(task.ramp.value(float(t))) for t in ev.d31_times_s]
            # the body's heading at each leg-1 touchdown, deg (a slope sweep must still walk up
            # and down the slope: `gait.HEADING_KEPT_DEG`)
            k = np.searchsorted(ser.times_s, ev.d31_times_s).clip(0, max(0, ser.times_s.size - 1))
            yaw = np.degrees(yaw_of(ser.body_quat[k])) if ser.times_s.size else np.zeros(0)
            item["heading_deg"] = [float(x) for x in yaw]
            item["touchdowns_s"] = [t.tolist() for t in ev.touchdowns_s]
            item["liftoffs_s"] = [t.tolist() for t in ev.liftoffs_s]
        out.append(item)
    return out


# What a task's result holds besides its run's summary (`RunResult.summary`): its leg-1
# touchdown times and compute time always, a surface probe's and a ramp's own records
EXTRA_KEYS = frozenset(
    {"d31_times_s", "compute_s", "touchdowns_s", "touchdown_phases", "value", "heading_deg",
     "liftoffs_s"}
)  # fmt: skip


def summary_of(result: dict[str, Any]) -> dict[str, Any]:
    """A task's result (`execute_chunk`) as its run's `RunResult.summary()`, in its order (a
    non-finite measure is null: JSON has no NaN)."""
    return {k: v for k, v in result.items() if k not in EXTRA_KEYS}


def make_chunks(tasks: Sequence[Task], chunk_size: int, workers: int = 1) -> list[list[Task]]:
    """Compatible tasks, at most `chunk_size` per chunk, the work balanced over `workers`,
    most work first.

    Tasks are first dealt to `workers` shares of equal simulated time (longest first, each to
    the lightest share), and each share is then cut into batches of compatible tasks: so a
    round of 136 runs on 2 workers is 18 batches of 7-8, not 17 of 8 that leave one worker a
    batch behind, and a long ramp fills one share while the short runs fill the other.
    Ordered longest first, so a long ramp starts early instead of last.
    """
    if chunk_size < 1:
        raise ValueError("chunk_size must be >= 1")
    shares: list[list[Task]] = [[] for _ in range(max(1, workers))]
    load = [0.0] * len(shares)
    for t in sorted(tasks, key=lambda t: (-t.duration_s, t.key)):
        k = load.index(min(load))
        shares[k].append(t)
        load[k] += t.duration_s
    chunks: list[list[Task]] = []
    for share in shares:
        groups: dict[tuple[Any, ...], list[Task]] = {}
        for t in share:
            groups.setdefault(t.group(), []).append(t)
        for members in groups.values():
            size = math.ceil(len(members) / math.ceil(len(members) / chunk_size))
            chunks.extend(members[k : k + size] for k in range(0, len(members), size))
    return sorted(chunks, key=lambda c: -sum(t.duration_s for t in c))

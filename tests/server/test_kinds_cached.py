"""Every kind's simulations go through the shared result cache (`server.kinds.compute`), and
that changes no result: each kind's stored result equals the one its runner computed before
issue 54, rebuilt here from the core's direct calls (`simulate_batch`, `sweep` without a cache,
`find` on `simulate_batch` rounds); run again on the same cache, every simulation is read back
(the record's counts say so) and the result is the same bytes. Real simulations, in this
process."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import sim_core
from server.kinds import JOB_SPEC_ADAPTER, AnyJob, ComputeSettings, execute, open_compute
from server.kinds import stored_form as stored
from server.kinds.bifurcation import BifurcationJob, BifurcationJobResult
from server.kinds.common import summary_row
from server.kinds.hysteresis import HysteresisJob, HysteresisJobResult
from server.kinds.return_map import ReturnMapJob, ReturnMapJobResult
from server.kinds.run import RunJob, RunJobResult, series_tables
from server.kinds.sweep import SweepJob, SweepJobResult
from sim_core import find, research, return_map_from_series
from sim_core.contract import RETURN_MAP_SKIP, Cell, FinderOutput

SHORT = {"beta": 0.66, "duration_s": 0.4}
JOBS: dict[str, dict[str, Any]] = {
    "run": {"kind": "run", **SHORT, "d31_init": [1.0, 2.0, 3.0]},
    "run_series": {"kind": "run", **SHORT, "d31_init": [2.0], "include_series": True},
    "return_map": {"kind": "return_map", "beta": 0.66, "duration_s": 0.6,
                   "d31_init": [1.0, 3.0], "lag": 1},
    "sweep": {"kind": "sweep", "beta_range": {"start": 0.62, "stop": 0.70, "steps": 3},
              "d31_init": [2.0, 3.0], "duration_s": 0.4, "body_mass_g": 4.0},
    "hysteresis": {"kind": "hysteresis", "ramp": {"param": "beta", "start": 0.70, "turn": 0.64,
                   "hold_s": 0.1, "ramp_s": 0.3}},
    "bifurcation": {"kind": "bifurcation", "beta_range": {"start": 0.62, "stop": 0.66,
                    "steps": 2}, "starts": 2, "duration_s": 2.0, "max_borders": 0,
                    "kick_rad": 0.0, "neighbour_seeds": False},
}  # fmt: skip


def _before_issue_54(job: AnyJob) -> dict[str, Any]:
    """The job's result as its kind computed it before issue 54: the core called directly,
    no cache (the runners of the time, rebuilt from the core's public calls)."""
    params = job.model_params()
    if isinstance(job, RunJob | ReturnMapJob):
        specs = [job.spec(beta=job.beta, d31_init=d, duration_s=job.duration_s)
                 for d in job.d31_init]  # fmt: skip
        results = sim_core.simulate_batch(specs, params, nthread=1)
        summaries = [r.summary() for r in results]
        if isinstance(job, ReturnMapJob):
            records = []
            for d0, r in zip(job.d31_init, results, strict=True):
                rm = return_map_from_series(job.beta, [r.events.d31], lag=job.lag)
                pairs = zip(rm.x.tolist(), rm.y.tolist(), strict=True)
                records += [{"d31_init": d0, "n": RETURN_MAP_SKIP + k, "d31_n": x,
                             "d31_n_plus_lag": y} for k, (x, y) in enumerate(pairs)]  # fmt: skip
            return stored(job, ReturnMapJobResult(beta=job.beta, lag=job.lag, records=records,
                                                  runs=summaries))  # fmt: skip
        runs = [r.to_dict() for r in results] if job.include_series else summaries
        return stored(job, RunJobResult(
            runs=runs, records=[summary_row(d, s) for d, s in zip(job.d31_init, summaries,
                                                                  strict=True)],
            warnings=list(dict.fromkeys(w for r in results for w in r.measures.warnings)),
            series=series_tables(job.d31_init, runs) if job.include_series else None,
        ))  # fmt: skip
    if isinstance(job, SweepJob):
        pairs = [(b, d) for b in job.beta_range.values() for d in job.d31_init]
        specs = [job.spec(beta=b, d31_init=d, duration_s=job.duration_s) for b, d in pairs]
        results = sim_core.simulate_batch(specs, params, nthread=1)
        records = [summary_row(d, r.summary()) | {"beta": b}
                   for (b, d), r in zip(pairs, results, strict=True)]  # fmt: skip
        warnings = list(dict.fromkeys(w for r in results for w in r.measures.warnings))
        return stored(job, SweepJobResult(records=records, warnings=warnings))
    if isinstance(job, HysteresisJob):
        ramp = job.ramp
        res = sim_core.sweep(job.start_spec(), parameter=ramp.param,
                             turn=ramp.turn, hold_s=ramp.hold_s, ramp_s=ramp.ramp_s,
                             params=params)  # fmt: skip
        turn_t = ramp.hold_s + ramp.ramp_s
        records = [{"time_s": t, "leg": "first" if t < turn_t else "second", "value": v, "d31": d}
                   for t, v, d in zip(res.times_s, res.values, res.d31, strict=True)]  # fmt: skip
        return stored(job, HysteresisJobResult(parameter=ramp.param, start=ramp.start,
                                               turn=ramp.turn, summary=res.summary,
                                               records=records))  # fmt: skip
    assert isinstance(job, BifurcationJob)

    def rounds(batch: list[Any]) -> list[dict[str, Any]]:  # the finder's runner of the time
        specs = [job.spec(**p.spec_fields(), **c.spec_fields()) for c, p in batch]
        results = sim_core.simulate_batch(specs, params, nthread=1)
        return [{"d31": r.events.d31.tolist(), "error": r.error,
                 "duration_s": r.measures.duration_s or p.duration_s}
                for r, (_, p) in zip(results, batch, strict=True)]  # fmt: skip

    from dataclasses import asdict

    from server.kinds.finder import finder_rows

    cells = [Cell(beta=b, body_mass_g=job.body_mass_g, slope_deg=job.slope_deg)
             for b in job.beta_range.values()]  # fmt: skip
    found = find(cells, job.finder_config(), rounds)
    out = FinderOutput(source="REST bifurcation job: the settled fixed-point finder",
                       config=asdict(job.finder_config()), cells=found)  # fmt: skip
    return stored(job, BifurcationJobResult(finder=out, records=finder_rows(found)))


@pytest.mark.parametrize("name", sorted(JOBS))
def test_a_kind_through_the_cache_gives_the_same_bytes_and_reads_them_back(
    name: str, tmp_path: Path
) -> None:
    job = JOB_SPEC_ADAPTER.validate_python(JOBS[name])
    where = ComputeSettings(cache_dir=tmp_path / "cache")
    first = open_compute(where, lambda _: None, 1)
    computed = execute(job, first)
    again = open_compute(where, lambda _: None, 1)
    replayed = execute(job, again)
    assert json.dumps(replayed) == json.dumps(computed) == json.dumps(_before_issue_54(job))
    made, read = first.counts(), again.counts()
    assert made.tasks == made.computed >= 1 and made.from_cache == 0, made
    if name == "run_series":  # series are not cached: computed each time, and said so
        assert read.computed == read.tasks == made.tasks and read.from_cache == 0
        assert not list((tmp_path / "cache").glob("*.json"))
    else:
        assert read.from_cache == read.tasks == made.tasks and read.computed == 0, read
        assert len(list((tmp_path / "cache").glob("*.json"))) == made.tasks
    assert made.backend == read.backend == "inline"


def test_a_finder_job_with_default_numerics_shares_reproduces_keys(tmp_path: Path) -> None:
    """The REST finder's runs are `reproduce`'s finder runs (`probe_task`): same keys."""
    job = JOB_SPEC_ADAPTER.validate_python(JOBS["bifurcation"])
    execute(job, open_compute(ComputeSettings(cache_dir=tmp_path), lambda _: None, 1))
    cells = [Cell(beta=b, body_mass_g=3.0, slope_deg=0.0) for b in (0.62, 0.66)]
    probes = [(c, p) for c in cells for p in _first_round(job)]
    keys = {research.probe_task(c, p, job.model_params()).key for c, p in probes}
    assert keys <= {p.stem for p in tmp_path.glob("*.json")}


def _first_round(job: Any) -> list[Any]:
    from sim_core.contract import Probe
    from sim_core.research import initial_values

    return [Probe(float(x), job.duration_s) for x in initial_values(job.starts)]

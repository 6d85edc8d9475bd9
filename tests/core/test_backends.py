"""Backends on real (tiny) simulations: a task computes what `simulate` computes, the local
process pool and a Dask LocalCluster give identical results, and the CLI's refusals."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from sim_core import RunSpec, simulate
from sim_core.cli.main import main
from sim_core.runs.backends import (
    BackendUnavailable,
    DaskBackend,
    InlineBackend,
    LocalBackend,
    get_backend,
    run_tasks,
)
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import Ramp, execute_chunk, ramp_task, run_task

HAS_DASK = importlib.util.find_spec("distributed") is not None


def _tiny() -> list:
    runs = [run_task(RunSpec(beta=0.66, d31_init=x, duration_s=0.3)) for x in (1.5, 2.5, 3.5)]
    ramp = ramp_task(Ramp("body_mass_g", 3.0, 4.0, 0.05, 0.1), RunSpec(beta=0.66))
    return [*runs, ramp]


def _without_timing(results: dict) -> dict:
    return {k: {f: v for f, v in r.items() if f != "compute_s"} for k, r in results.items()}


def test_a_task_computes_what_simulate_computes() -> None:
    spec = RunSpec(beta=0.62, d31_init=2.0, duration_s=0.4)
    (r,) = execute_chunk([run_task(spec)])
    ref = simulate(spec)
    np.testing.assert_array_equal(r["d31"], ref.events.d31)
    assert r["error"] is None and r["speed_cm_s"] == ref.measures.speed_cm_s


def test_a_ramp_task_follows_its_schedule() -> None:
    ramp = Ramp("beta", 0.70, 0.64, 0.1, 0.2)
    (r,) = execute_chunk([ramp_task(ramp, RunSpec(beta=0.70, d31_init=1.9))])
    sched = ramp.schedule()
    assert r["error"] is None and len(r["value"]) == len(r["d31"]) > 3
    assert r["value"] == [sched(t) for t in r["d31_times_s"]]
    assert min(r["value"]) < 0.66 and len(r["touchdowns_s"]) == 6


@pytest.mark.skipif(not HAS_DASK, reason="dask.distributed not installed (extra 'cluster')")
def test_local_pool_and_dask_cluster_give_identical_results(tmp_path: Path) -> None:
    tasks = _tiny()
    inline, _ = run_tasks(tasks, ResultCache(tmp_path / "a"), InlineBackend(), progress=False)
    local = LocalBackend(2)
    try:  # two rounds on one pool (the finder's way): the second reuses its processes
        pool, stats = run_tasks(tasks, ResultCache(tmp_path / "b"), local, chunk_size=2,
                                progress=False)  # fmt: skip
        again, _ = run_tasks(tasks, ResultCache(tmp_path / "d"), local, chunk_size=1,
                             progress=False)  # fmt: skip
    finally:
        local.close()
    assert stats.computed == len(tasks)
    assert _without_timing(again) == _without_timing(pool)
    dask = DaskBackend(workers=1, processes=False)
    try:
        assert dask.workers == 1
        remote, _ = run_tasks(tasks, ResultCache(tmp_path / "c"), dask, chunk_size=1,
                              progress=False)  # fmt: skip
    finally:
        dask.close()
    assert _without_timing(inline) == _without_timing(pool) == _without_timing(remote)


def test_unsupported_backends_say_why() -> None:
    with pytest.raises(BackendUnavailable, match="dask"):
        get_backend("ray")
    with pytest.raises(BackendUnavailable, match="--backend dask"):
        get_backend("local", address="tcp://127.0.0.1:8786")


@pytest.mark.parametrize(
    "args",
    [["--backend", "ray"], ["--address", "tcp://127.0.0.1:1"], ["--workers", "0"],
     ["--figure", "10"], ["--doc", "/nonexistent.md"]],
)  # fmt: skip
def test_reproduce_cli_refusals_exit_2(args: list[str], capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main(["reproduce", "--quick", *args]))
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert "error" in err and "Traceback" not in err


def test_reproduce_cli_quick_ablation(tmp_path: Path, capsys) -> None:
    out, cache = tmp_path / "out", tmp_path / "cache"
    args = ["reproduce", "--quick", "--figure", "ablation", "--out", str(out), "--cache",
            str(cache), "--workers", "1", "--no-progress"]  # fmt: skip
    assert main(args) == 0
    text = capsys.readouterr().out
    assert "no phase resetting" in text and "2 of 2 simulations computed" in text
    assert (out / "ablation.png").is_file() and (out / "reproduce_table.md").is_file()
    assert main(args) == 0
    assert "0 of 2 simulations computed" in capsys.readouterr().out


@pytest.mark.skipif(not HAS_DASK, reason="dask.distributed not installed (extra 'cluster')")
def test_reproduce_cli_on_a_running_dask_scheduler(tmp_path: Path, capsys) -> None:
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address=None) as cluster:  # fmt: skip
        args = ["reproduce", "--quick", "--figure", "ablation", "--backend", "dask",
                "--address", cluster.scheduler_address, "--out", str(tmp_path / "out"),
                "--cache", str(tmp_path / "cache"), "--no-progress"]  # fmt: skip
        assert main(args) == 0
    out = capsys.readouterr().out
    assert "`dask` backend with 1 worker(s)" in out and "2 of 2 simulations computed" in out

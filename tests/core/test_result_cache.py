"""The result cache shared by every door: where it is (one definition, an environment override),
its bound (least recently used evicted, never a file being written), `insect-gait cache`, and
what a task's result reads back as (`summary_of`: the run's own summary)."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import pytest

from sim_core import RunSpec, simulate
from sim_core.cli.main import main
from sim_core.runs import (
    CACHE_DIR_ENV,
    CACHE_MAX_BYTES_ENV,
    DEFAULT_CACHE_MAX_BYTES,
    cache_max_bytes_of,
    default_cache_dir,
    default_cache_max_bytes,
)
from sim_core.runs.backends import InlineBackend, run_tasks
from sim_core.runs.cache import STALE_TMP_S, ResultCache
from sim_core.runs.tasks import Task, execute_chunk, run_task, summary_of

REPO = Path(__file__).resolve().parents[2]


def _fake(i: int) -> Task:
    """A task that is never run: a distinct key per i (the cache stores what it is given)."""
    return run_task(RunSpec(beta=0.6 + i * 1e-4, duration_s=0.1))


def _fill(cache: ResultCache, n: int, size: int = 1000) -> list[Task]:
    tasks = [_fake(i) for i in range(n)]
    for k, t in enumerate(tasks):
        cache.put(t, {"pad": "x" * size})
        os.utime(cache.path(t), (1000.0 + k, 1000.0 + k))  # written in this order
    return tasks


def test_the_default_location_is_defined_once_and_overridable(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.delenv(CACHE_DIR_ENV, raising=False)
    assert default_cache_dir() == REPO / "out" / "cache"  # a checkout: its out/cache
    monkeypatch.setenv(CACHE_DIR_ENV, str(tmp_path / "shared"))
    assert default_cache_dir() == tmp_path / "shared"
    # the CLI's --cache default is that folder (read when the parser is built)
    from sim_core.cli.main import build_parser

    args = build_parser().parse_args(["reproduce", "--quick"])
    assert Path(args.cache) == tmp_path / "shared"
    # and the service's setting
    from server.settings import Settings

    assert Settings().cache_dir == tmp_path / "shared"


def test_the_size_limit_reads_alike_everywhere(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(CACHE_MAX_BYTES_ENV, raising=False)
    assert default_cache_max_bytes() == DEFAULT_CACHE_MAX_BYTES
    for text, want in (("123", 123), ("0", None), ("none", None), (" NONE ", None)):
        assert cache_max_bytes_of(text) == want
        monkeypatch.setenv(CACHE_MAX_BYTES_ENV, text)
        assert default_cache_max_bytes() == want
        from server.settings import Settings

        assert Settings().cache_max_bytes == want
    for bad in ("-1", "2GB", "1.5"):
        with pytest.raises(ValueError, match=CACHE_MAX_BYTES_ENV):
            cache_max_bytes_of(bad)


def test_a_read_makes_a_result_the_last_to_go(tmp_path: Path) -> None:
    cache = ResultCache(tmp_path)
    tasks = _fill(cache, 10)
    sizes = {t.key: cache.path(t).stat().st_size for t in tasks}
    per = max(sizes.values())
    assert cache.get(tasks[0]) == {"pad": "x" * 1000}  # the oldest written, now used
    # over a limit of 5 results: down to 90% of it, the least recently used first
    gone = cache.trim(5 * per)
    kept = {t.key for t in tasks if cache.path(t).exists()}
    assert gone.entries == 10 - len(kept)
    assert gone.bytes == sum(n for k, n in sizes.items() if k not in kept)
    assert cache.usage().bytes <= 0.9 * 5 * per
    assert tasks[0].key in kept  # read last: kept
    assert kept == {tasks[0].key} | {t.key for t in tasks[-len(kept) + 1 :]}
    assert cache.trim(5 * per).entries == 0  # within the limit: nothing more
    assert ResultCache(tmp_path, max_bytes=None).trim().entries == 0  # no limit: no eviction


def test_a_trim_never_touches_a_file_being_written(tmp_path: Path) -> None:
    cache = ResultCache(tmp_path)
    _fill(cache, 4)
    writing = tmp_path / f".{_fake(99).key}.abc123.tmp"  # another process's write, now
    writing.write_text("{")
    left = tmp_path / f".{_fake(98).key}.def456.tmp"  # a killed writer's, an hour ago
    left.write_text("{")
    old = time.time() - STALE_TMP_S - 60
    os.utime(left, (old, old))
    other = tmp_path / "notes.txt"  # not the cache's: never touched
    other.write_text("mine")
    assert cache.usage().temporary == 2
    gone = cache.trim(1)
    assert gone.entries == 4 and gone.temporary == 1
    assert writing.exists() and not left.exists() and other.exists()
    _fill(cache, 2)
    assert cache.clear().entries == 2 and writing.exists() and other.exists()


def test_run_tasks_keeps_a_bounded_cache_within_its_limit(tmp_path: Path) -> None:
    """A run that adds results trims afterwards: the oldest go, the ones it used stay."""
    cache = ResultCache(tmp_path)
    old = _fill(cache, 6, size=4000)
    spec = RunSpec(beta=0.66, duration_s=0.2)
    limit = 6 * cache.path(old[0]).stat().st_size
    bounded = ResultCache(tmp_path, max_bytes=limit)
    _, stats = run_tasks([run_task(spec)], bounded, InlineBackend(), progress=False)
    assert stats.computed == 1 and bounded.usage().bytes <= limit
    assert bounded.path(run_task(spec)).exists() and not cache.path(old[0]).exists()


def test_a_tasks_result_reads_back_as_the_runs_summary() -> None:
    """`summary_of` is `RunResult.summary()`: the same keys in the same order, the same
    numbers, for a plain run and for a failed one; a ramp's extras are dropped too."""
    for spec in (RunSpec(beta=0.62, d31_init=2.0, duration_s=0.4),
                 RunSpec(beta=0.66, slope_deg=89.9, duration_s=1.0)):  # fmt: skip
        (item,) = execute_chunk([run_task(spec)])
        want = json.loads(json.dumps(simulate(spec).summary()))
        assert list(summary_of(item)) == list(want)
        assert summary_of(item) == want
    assert summary_of(item)["failure"] is not None  # the 89.9 deg run slid back


def test_threads_change_no_number() -> None:
    """`execute_chunk(nthread=...)`: a service worker with several cores steps its chunk's
    physics on them; each simulation is stepped alone, so the numbers are the same bits."""
    tasks = [run_task(RunSpec(beta=0.66, d31_init=x, duration_s=0.3)) for x in (1.0, 2.5, 4.0)]
    one = execute_chunk(tasks)
    two = execute_chunk(tasks, nthread=2)
    strip = [{k: v for k, v in r.items() if k != "compute_s"} for r in one]
    assert strip == [{k: v for k, v in r.items() if k != "compute_s"} for r in two]


def test_the_cache_command_shows_and_tidies_the_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    cache = ResultCache(tmp_path / "c")
    tasks = _fill(cache, 5)
    monkeypatch.setenv(CACHE_DIR_ENV, str(tmp_path / "c"))
    assert main(["cache", "info", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["location"] == str((tmp_path / "c").resolve()) and info["entries"] == 5
    assert info["bytes"] == sum(cache.path(t).stat().st_size for t in tasks)
    assert info["max_bytes"] == default_cache_max_bytes()
    assert main(["cache", "info"]) == 0
    words = capsys.readouterr().out
    assert str((tmp_path / "c").resolve()) in words and "5 result(s)" in words and "limit" in words
    per = min(cache.path(t).stat().st_size for t in tasks)
    assert main(["cache", "trim", "--max-bytes", str(3 * per), "--json"]) == 0
    trimmed = json.loads(capsys.readouterr().out)
    assert trimmed["removed"] == 3 and trimmed["entries"] == 2  # down to 90% of 3 results
    assert main(["cache", "clear"]) == 0
    assert "removed 2 result(s)" in capsys.readouterr().out
    assert cache.usage().entries == 0
    assert main(["cache", "info", "--max-bytes", "lots"]) == 2
    assert "--max-bytes" in capsys.readouterr().err


def test_a_loop_of_small_runs_scans_the_folder_only_when_it_may_be_over(tmp_path: Path) -> None:
    """`maybe_trim` (what run_tasks calls) rescans only when this cache's own writes could
    have passed the limit, or a minute after its last scan (other processes write too)."""
    cache = ResultCache(tmp_path, max_bytes=10_000)
    _fill(cache, 3)
    assert cache.maybe_trim() is not None  # never scanned: scans
    assert cache.maybe_trim() is None  # just scanned, under the limit, nothing written
    _fill(ResultCache(tmp_path), 20)  # another process writes: unseen until the minute is up
    assert cache.maybe_trim() is None
    assert cache.maybe_trim(every_s=0.0) is not None  # the minute is up: scanned and trimmed
    assert cache.usage().bytes <= 10_000
    for i in range(30, 60):  # this object's own writes count towards a rescan
        cache.put(_fake(i), {"pad": "x" * 1000})
    gone = cache.maybe_trim()
    assert gone is not None and gone.entries > 0 and cache.usage().bytes <= 10_000
    assert ResultCache(tmp_path).maybe_trim() is None  # no limit: never scans

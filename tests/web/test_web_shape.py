"""The viewer's shape rules (issue 53): web/ is built by composition, its functions stay simple
and its modules small.

- No class of web/ extends a chain of web/ classes: a class may extend at most one class of
  web/, and that one extends none (a part may refine one base; no tower of mixins).
- No function of web/ has a McCabe complexity above 15 (ruff's C901, configured for web/ in
  pyproject.toml so that `ruff check .` holds it too; checked here against the same setting).
- No module of web/ is longer than 250 lines.

Each rule is read off the source (ast, ruff), and each checker is first shown to catch what it
forbids on a small made-up package.
"""

from __future__ import annotations

import ast
import subprocess
import sys
import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
WEB = REPO / "web"
MAX_LINES = 250
MAX_COMPLEXITY = 15


def _sources(folder: Path) -> dict[str, str]:
    """Module name (web.x) -> source, for every module of the package in `folder`."""
    return {f"{folder.name}.{p.stem}": p.read_text() for p in sorted(folder.glob("*.py"))}


def base_chains(sources: dict[str, str], package: str = "web") -> dict[str, list[str]]:
    """Each class of `package` (module.Class) -> the classes of `package` it extends directly,
    resolved through the module's own classes and its `from package.x import Name` imports."""
    classes: dict[str, dict[str, ast.ClassDef]] = {}
    trees = {m: ast.parse(src) for m, src in sources.items()}
    for module, tree in trees.items():
        classes[module] = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    out: dict[str, list[str]] = {}
    for module, tree in trees.items():
        names = {name: f"{module}.{name}" for name in classes[module]}
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith(package + "."):
                for alias in node.names:
                    if alias.name in classes.get(node.module or "", {}):
                        names[alias.asname or alias.name] = f"{node.module}.{alias.name}"
        for cls in classes[module].values():
            bases = []
            for base in cls.bases:
                if isinstance(base, ast.Name) and base.id in names:
                    bases.append(names[base.id])
                elif isinstance(base, ast.Attribute) and ast.unparse(base).startswith(package):
                    bases.append(ast.unparse(base))
            out[f"{module}.{cls.name}"] = bases
    return out


def depth(cls: str, bases: dict[str, list[str]]) -> int:
    """How many classes of the package lie above `cls` on its longest chain."""
    return max((1 + depth(b, bases) for b in bases.get(cls, [])), default=0)


def too_deep(sources: dict[str, str], package: str = "web") -> list[str]:
    """Classes that extend more than one class of the package, or a chain deeper than one."""
    bases = base_chains(sources, package)
    return sorted(c for c, bs in bases.items() if len(bs) > 1 or depth(c, bases) > 1)


def test_the_class_rule_catches_a_tower_and_a_pair_of_mixins() -> None:
    made_up = {
        "web.a": "class State:\n    pass\n\nclass Part(State):\n    pass\n",
        "web.b": "from web.a import Part, State\n\nclass Tower(Part):\n    pass\n\n"
        "class Mixed(Part, State):\n    pass\n\nclass Fine(State):\n    pass\n",
        "web.c": "import web.b\n\nclass Dotted(web.b.Tower):\n    pass\n",
    }
    assert too_deep(made_up) == ["web.b.Mixed", "web.b.Tower", "web.c.Dotted"]


def test_no_class_of_web_extends_a_chain_of_web_classes() -> None:
    sources = _sources(WEB)
    assert len(base_chains(sources)) > 30  # every class was read
    assert too_deep(sources) == []


def _ruff_c901(path: Path) -> subprocess.CompletedProcess[str]:
    """ruff's McCabe check of `path` with the limit pyproject.toml sets."""
    args = ["--select", "C901", "--config", f"lint.mccabe.max-complexity={MAX_COMPLEXITY}"]
    return subprocess.run(
        [sys.executable, "-m", "ruff", "check", "--no-cache", "--isolated", *args, str(path)],
        capture_output=True,
        text=True,
        cwd=REPO,
    )


def test_no_function_of_web_is_more_complex_than_15(tmp_path: Path) -> None:
    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["ruff"]["lint"]
    assert "C901" in config["select"] and config["mccabe"]["max-complexity"] == MAX_COMPLEXITY
    assert all("C901" not in v for k, v in config["per-file-ignores"].items() if "web" in k and
               not k.startswith("!"))  # fmt: skip
    branches = "".join(f"    if x == {i}:\n        return {i}\n" for i in range(MAX_COMPLEXITY))
    (tmp_path / "branchy.py").write_text(f"def f(x: int) -> int:\n{branches}    return -1\n")
    caught = _ruff_c901(tmp_path / "branchy.py")
    assert caught.returncode == 1 and "C901" in caught.stdout, caught.stdout + caught.stderr
    web = _ruff_c901(WEB)
    assert web.returncode == 0, web.stdout + web.stderr


def test_no_module_of_web_is_longer_than_250_lines() -> None:
    lengths = {p.name: len(p.read_text().splitlines()) for p in WEB.glob("*.py")}
    assert len(lengths) > 30
    assert {name: n for name, n in lengths.items() if n > MAX_LINES} == {}

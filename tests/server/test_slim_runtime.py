"""The runtime is slim: optuna (with SQLAlchemy and alembic, ~37 MB) is the lab's, an extra
that `make test` installs and `make install`, `make run` and the image do not. The product
(sim_core, server, web) must therefore import, and start its commands, without it. That no
source of the product imports them, even inside a function, is an import-linter contract in
pyproject.toml (`lint-imports`); what a fresh interpreter loads is checked here."""

from __future__ import annotations

import subprocess
import sys
import tomllib

from api_harness import REPO

LAB_ONLY = ("optuna", "sqlalchemy", "alembic")
PRODUCT = ("sim_core", "server", "web")

# A meta-path finder that refuses the lab's packages, as an interpreter without them would.
BLOCKER = f"""
import importlib.abc, sys
class Absent(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in {LAB_ONLY!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}} (blocked)", name=name)
        return None
sys.meta_path.insert(0, Absent())
"""


def test_every_module_of_the_product_imports_without_the_lab_packages() -> None:
    """Each module of sim_core, server and web, imported in a fresh interpreter that cannot
    find optuna; then the app, the viewer's and the CLI's parsers are built (what `make run`
    starts first)."""
    code = BLOCKER + (
        "import importlib, importlib.util, pkgutil\n"
        "n = 0\n"
        f"for top in {PRODUCT!r}:\n"
        "    pkg = importlib.import_module(top)\n"
        "    for m in pkgutil.walk_packages(pkg.__path__, top + '.'):\n"
        "        origin = importlib.util.find_spec(m.name).origin or ''\n"
        "        # Python sources only (the ground's plugin is a MuJoCo library, not a module)\n"
        "        if origin.endswith('.py') and not m.name.endswith('__main__'):\n"
        "            importlib.import_module(m.name)\n"
        "            n += 1\n"
        "print('modules', n)\n"
        "from server.app import create_app\n"
        "create_app()\n"
        "from sim_core.cli import build_parser\n"
        "build_parser().parse_args(['viewer', '--help'])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True,
                         text=True, timeout=300)  # fmt: skip
    # `--help` exits 0 after printing the viewer's options (the plug-in command loaded)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "--api-url" in out.stdout
    assert int(out.stdout.split("modules ")[1].split()[0]) > 100


def test_the_blocker_blocks() -> None:
    """The check above can fail: with the blocker, importing optuna raises."""
    out = subprocess.run([sys.executable, "-c", BLOCKER + "import optuna"], cwd=REPO,
                         capture_output=True, text=True, timeout=60)  # fmt: skip
    assert out.returncode != 0 and "blocked" in out.stderr


def test_optuna_is_an_extra_of_the_lab_and_of_make_test_only() -> None:
    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    runtime = " ".join(project["dependencies"]).lower()
    assert not any(name in runtime for name in LAB_ONLY), runtime
    assert any(d.startswith("optuna") for d in project["optional-dependencies"]["lab"])
    make = (REPO / "Makefile").read_text()
    dev = [ln for ln in make.splitlines() if "pip install" in ln and "-e '.[" in ln]
    assert dev and all("lab" in ln.split("-e '.[")[1].split("]")[0] for ln in dev), dev
    plain = [ln for ln in make.splitlines() if "pip install" in ln and ln.rstrip().endswith(
        "-e . 2>&1 | grep -v -i setuptools || true")]  # fmt: skip
    assert len(plain) == 1  # `make install` / `make run`: the package without extras

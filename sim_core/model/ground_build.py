"""Compile the penalty ground's MuJoCo plugin: `python -m sim_core.model.ground_build`.

`make run`, `make test` (through `make plugin`) and the Dockerfile's build stage run it after
installing the project. It compiles `penalty_ground.c` against the headers that ship in the
installed mujoco wheel and links it to that wheel's libmujoco (by soname, which names the exact
MuJoCo version: a library built for another MuJoCo refuses to load instead of misreading its
structs). Imports only mujoco, so it runs before anything else of sim_core works.
"""

from __future__ import annotations

import hashlib
import os
import shlex
import subprocess
import sys
import sysconfig
from pathlib import Path

import mujoco

HERE = Path(__file__).parent
SOURCE = HERE / "penalty_ground.c"
LIBRARY = HERE / "libpenalty_ground.so"
# every product and sum rounds as written (no fused multiply-add), on every target
CFLAGS = ["-std=c11", "-O2", "-fPIC", "-ffp-contract=off", "-Wall", "-Wextra"]


def plugin_name() -> str:
    """The name the plugin registers under: it carries a hash of the source, so a library
    built from another version of penalty_ground.c is not found (`ground.load_plugin` then
    says to rebuild) instead of silently computing other numbers."""
    digest = hashlib.sha256(SOURCE.read_bytes()).hexdigest()[:12]
    return f"insect_gait.penalty_ground.{digest}"


def compile_command(output: Path) -> list[str]:
    """The compiler call that builds the plugin into `output`."""
    mj = Path(mujoco.__file__).parent
    cc = os.environ.get("CC") or str(sysconfig.get_config_var("CC") or "cc")
    libmujoco = f"libmujoco.so.{mujoco.__version__}"  # the soname names the exact version
    return [
        *shlex.split(cc), *CFLAGS, "-shared", f'-DPLUGIN_NAME="{plugin_name()}"',
        f"-I{mj / 'include'}", str(SOURCE), "-o", str(output), f"-L{mj}", f"-l:{libmujoco}", "-lm",
    ]  # fmt: skip


def build(output: Path = LIBRARY) -> Path:
    """Compile the plugin to `output` (written under a temporary name, then renamed)."""
    tmp = output.with_suffix(f".{os.getpid()}.tmp")
    try:
        subprocess.run(compile_command(tmp), check=True)
        tmp.replace(output)
    finally:
        tmp.unlink(missing_ok=True)
    return output


if __name__ == "__main__":
    print(build(Path(sys.argv[1]) if len(sys.argv) > 1 else LIBRARY))

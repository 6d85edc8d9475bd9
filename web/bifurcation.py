"""Read the finder's typed results for the bifurcation and atlas panels.

`insect-gait finder` writes bifurcation.json as a `FinderOutput` and `python -m lab
finder-atlas` writes atlas_<axis>.json as an `AtlasOutput` (sim_core.contract.finder, in the
MuJoCo-free `sim_core.contract`). The viewer validates them with those very models: no guessing
at shapes. A file that is absent or does not validate gives a one-line note for the panel,
naming the first validation error, instead of a drawing.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Generic, TypeVar

from pydantic import BaseModel, ValidationError

from sim_core.contract import TWO_PI, FinderOutput

M = TypeVar("M", bound=BaseModel)


def first_error(exc: ValidationError) -> str:
    """'cells.0.beta: Field required (3 errors)': where and what, in one line."""
    errors = exc.errors()
    if not errors:
        return str(exc).splitlines()[0]
    e = errors[0]
    loc = ".".join(str(x) for x in e.get("loc", ())) or "(top level)"
    more = f" ({len(errors)} errors)" if len(errors) > 1 else ""
    return f"{loc}: {e.get('msg', '')}{more}"


def load_validated(path: Path, model: type[M], what: str) -> tuple[M | None, str]:
    """The file validated as `model`, and a note for the panel ("" when all is well)."""
    try:
        text = path.read_text()
    except FileNotFoundError:
        return None, f"no {what}: {path} absent"
    except OSError as exc:
        return None, f"cannot read {path.name}: {exc}"
    try:
        return model.model_validate_json(text), ""
    except ValidationError as exc:
        return None, f"{path.name} is not a {model.__name__}: {first_error(exc)}"


class WatchedFile(Generic[M]):
    """A result file re-read whenever it appears, changes or goes away (by mtime)."""

    def __init__(self, path: Path, model: type[M], what: str) -> None:
        self.path = path
        self.model = model
        self.what = what
        self._mtime: float | None = -1.0
        self._value: tuple[M | None, str] = (None, "")
        # bumps on every (re)read: a redraw key that cannot collide, as an object's id can
        self.version = 0

    def get(self) -> tuple[M | None, str]:
        try:
            mtime: float | None = self.path.stat().st_mtime
        except OSError:
            mtime = None
        if mtime != self._mtime:
            self._mtime = mtime
            self._value = load_validated(self.path, self.model, self.what)
            self.version += 1
        return self._value


@dataclass(frozen=True)
class FinderPoints:
    """What the bifurcation panel draws from a FinderOutput, as (beta, Delta31) points."""

    stable: list[tuple[float, float, str]] = field(default_factory=list)  # + gait
    unstable: list[tuple[float, float]] = field(default_factory=list)  # borders' saddles
    # settled states whose kicks came back from one side only (or neither): not stable points
    one_sided: list[tuple[float, float]] = field(default_factory=list)
    ghosts: list[tuple[float, float]] = field(default_factory=list)
    unsettled: list[tuple[float, float]] = field(default_factory=list)  # finals, not settled

    def __len__(self) -> int:
        return (len(self.stable) + len(self.unstable) + len(self.one_sided) + len(self.ghosts)
                + len(self.unsettled))  # fmt: skip


def finder_points(out: FinderOutput) -> FinderPoints:
    pts = FinderPoints()
    for c in out.cells:
        pts.stable.extend((c.beta, a.d31 % (TWO_PI), a.gait) for a in c.stable())
        pts.one_sided.extend((c.beta, a.d31 % (TWO_PI)) for a in c.one_sided())
        pts.unstable.extend((c.beta, b.d31 % (TWO_PI)) for b in c.borders if b.d31 is not None)
        pts.ghosts.extend((c.beta, g.d31 % (TWO_PI)) for g in c.ghosts)
        pts.unsettled.extend(
            (c.beta, r.final % (TWO_PI))
            for r in c.runs
            if not r.settled and r.failure is None and r.final is not None
        )
    return pts

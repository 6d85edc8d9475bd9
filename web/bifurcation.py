"""Read the experiments' cached bifurcation results, whatever shape the writer chose.

The experiments are written by another part of the project and their JSON layout may change; the
viewer only needs (beta, Delta31) points grouped into series (typically the sweep down and the
sweep up). So the reader walks the JSON and accepts the shapes a writer is likely to use:

- a point: `{"beta": 0.62, "d31_final": 2.9}` (also `d31`, `delta31`; a `direction`, `branch` or
  `sweep` field names its series), e.g. a list of `RunResult.summary()` dicts;
- columns: `{"beta": [...], "d31": [...]}` where each d31 entry may itself be a list;
- either of these nested under keys, whose names become series names (`{"down": ..., "up": ...}`).

Anything else is ignored; if nothing is found the panel says so instead of drawing nothing.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

TWO_PI = 2.0 * math.pi
_D31_KEYS = ("d31_final", "d31", "delta31", "d31_rad")
_SERIES_KEYS = ("direction", "branch", "sweep", "series")
DEFAULT_PATH = Path("docs/figures/bifurcation.json")

Series = dict[str, list[tuple[float, float]]]


def _num(v: Any) -> float | None:
    if isinstance(v, bool) or not isinstance(v, int | float):
        return None
    f = float(v)
    return f if math.isfinite(f) else None


def _add(out: Series, name: str, beta: float | None, d31: Any) -> None:
    if beta is None:
        return
    values = d31 if isinstance(d31, list) else [d31]
    for v in values:
        d = _num(v)
        if d is not None:
            out.setdefault(name, []).append((beta, d % TWO_PI))


def _walk(obj: Any, name: str, out: Series, depth: int = 0) -> None:
    if depth > 8:
        return
    if isinstance(obj, list):
        for item in obj:
            _walk(item, name, out, depth + 1)
        return
    if not isinstance(obj, dict):
        return
    series = next((str(obj[k]) for k in _SERIES_KEYS if isinstance(obj.get(k), str)), name)
    d31_key = next((k for k in _D31_KEYS if k in obj), None)
    beta = obj.get("beta")
    if d31_key is not None and beta is not None:
        d31 = obj[d31_key]
        if isinstance(beta, list) and isinstance(d31, list) and len(beta) == len(d31):
            for b, d in zip(beta, d31, strict=True):
                _add(out, series, _num(b), d)
        else:
            _add(out, series, _num(beta), d31)
        return
    for key, value in obj.items():
        if isinstance(value, dict | list):
            _walk(value, str(key) if name == "results" else name, out, depth + 1)


def extract_points(data: Any) -> Series:
    """(beta, Delta31) points per series found anywhere in parsed JSON."""
    out: Series = {}
    _walk(data, "results", out)
    return out


def load_bifurcation(path: Path = DEFAULT_PATH) -> tuple[Series | None, str]:
    """Cached points and a note for the panel (empty when all is well)."""
    if not path.exists():
        return None, f"no cached results: {path} absent"
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        return None, f"cannot read {path.name}: {exc}"
    points = extract_points(data)
    if not points:
        return None, f"{path.name}: no (β, Δ31) points found"
    return points, ""

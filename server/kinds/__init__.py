"""The job kinds: one module each (`server/kinds/<name>.py`: request model, runner, record
columns, figure, exported together as `KIND`), and the registry derived from `NAMES`.

Adding a kind is a new module and its name in `NAMES` (docs/API.md, "Adding a job kind").
Shared pieces: `bounds` (ranges as numbers and as words), `base` (the request bases and `Kind`),
`common` (the runners' and figures' helpers), `finder` (what the finder kinds share).

Importing this package loads neither MuJoCo nor matplotlib: the kinds `import sim_core`, whose
names load on first use (sim_core/__init__.pyi, typed for mypy), so MuJoCo loads when a runner
first calls the core (in a worker process); figures import matplotlib when they draw.
"""

from __future__ import annotations

import importlib
import math
from typing import TYPE_CHECKING, Annotated, Any, TypeAlias, Union

from pydantic import Field, TypeAdapter

from server.kinds.base import JobFailed, Kind, Physics, Result
from server.kinds.bounds import tidy
from server.kinds.compute import Compute, ComputeSettings, open_compute
from server.kinds.provenance import job_provenance

# The registry: one line per kind, in the order the request union (and so OpenAPI) lists them.
NAMES = (
    "run",
    "return_map",
    "sweep",
    "bifurcation",
    "hysteresis",
    "atlas",
    "surface",
)


def _load(name: str) -> Kind[Any]:
    kind = getattr(importlib.import_module(f"server.kinds.{name}"), "KIND", None)
    if not isinstance(kind, Kind) or kind.name != name:
        raise TypeError(f"server/kinds/{name}.py must export KIND = Kind(...) of kind {name!r}")
    return kind


KINDS: dict[str, Kind[Any]] = {name: _load(name) for name in NAMES}
KIND_MODELS: dict[str, type[Physics]] = {name: k.model for name, k in KINDS.items()}
RECORD_COLUMNS: dict[str, tuple[str, ...]] = {name: k.columns for name, k in KINDS.items()}
KIND_RESULTS: dict[str, type[Result]] = {name: k.result for name, k in KINDS.items()}

# A request: one of the kinds' models, told apart by `kind`. Built from the registry at run
# time, so type checkers see the models' common base.
if TYPE_CHECKING:
    AnyJob: TypeAlias = Physics
else:
    AnyJob = Union[tuple(k.model for k in KINDS.values())]  # noqa: UP007
JobSpec = Annotated[AnyJob, Field(discriminator="kind")]
JOB_SPEC_ADAPTER: TypeAdapter[AnyJob] = TypeAdapter(JobSpec)
# A result: one of the kinds' result models, told apart by `kind` (the schema in OpenAPI).
if TYPE_CHECKING:
    AnyResult: TypeAlias = Result
else:
    AnyResult = Union[tuple(k.result for k in KINDS.values())]  # noqa: UP007
ResultSpec = Annotated[AnyResult, Field(discriminator="kind")]
RESULT_ADAPTER: TypeAdapter[AnyResult] = TypeAdapter(ResultSpec)

__all__ = [
    "JOB_SPEC_ADAPTER",
    "KINDS",
    "KIND_MODELS",
    "KIND_RESULTS",
    "NAMES",
    "RECORD_COLUMNS",
    "RESULT_ADAPTER",
    "AnyJob",
    "AnyResult",
    "Compute",
    "ComputeSettings",
    "JobFailed",
    "JobSpec",
    "Kind",
    "ResultSpec",
    "execute",
    "open_compute",
    "stored_form",
]


def execute(job: AnyJob, compute: Compute) -> dict[str, Any]:
    """Run `job` by its kind's runner (in a worker process), its simulations through `compute`
    (which counts them); the result (its kind's `Result`, stamped with the job's provenance:
    every kind's, one function) as JSON-able data, a top-level null left out, checked finite
    and its floats tidied."""
    return stored_form(job, KINDS[job.kind_name()].run(job, compute))


def stored_form(job: AnyJob, outcome: Result) -> dict[str, Any]:
    """A runner's `outcome` as it is stored and served (`execute`): stamped, dumped, checked
    finite and tidied."""
    outcome = outcome.model_copy(update={"provenance": job_provenance(job)})
    data = outcome.model_dump(mode="json")  # keeps NaN and inf as floats: checked below
    result = {k: v for k, v in data.items() if v is not None}
    _check_finite(result)
    out: dict[str, Any] = _tidy(result)
    return out


def _tidy(obj: Any) -> Any:
    """Floats to 12 significant digits (0.66, not 0.6599999999999999): far below any physical
    resolution of the model, and what a person reads back is what they sent."""
    if isinstance(obj, float):
        return tidy(obj)
    if isinstance(obj, dict):
        return {k: _tidy(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_tidy(v) for v in obj]
    return obj


def _check_finite(obj: Any, path: str = "result") -> None:
    """JSON has no NaN; a non-finite number means a broken run, which must not pass as data."""
    if isinstance(obj, float) and not math.isfinite(obj):
        raise JobFailed(f"the simulation produced a non-finite number at {path}")
    if isinstance(obj, dict):
        for k, v in obj.items():
            _check_finite(v, f"{path}.{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            _check_finite(v, f"{path}[{i}]")

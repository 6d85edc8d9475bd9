"""The result cache's keys' parts, and a run's provenance, free of the engine.

Apart from `sim_core.runs.tasks` (which runs tasks, so loads MuJoCo) because the edges stamp
their files with the same parameter hash the cache and `reproduce` use, through the MuJoCo-free
contract: an export from the viewer, a job's CSV and a cached run then name their physics in
the same words (`provenance`), and a hash is never recomputed another way.
"""

from __future__ import annotations

import hashlib
import json
from typing import Any

from sim_core.model.params import ModelParams, leaf_values
from sim_core.model.spec import RunSpec
from sim_core.model.version import PHYSICS_VERSION


def canonical(obj: Any) -> str:
    """JSON with sorted keys and no spaces: equal content, equal text, equal hash."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False)


def params_json(params: ModelParams | None) -> str:
    """The parameters that differ from the defaults, flat by leaf name (`leaf_values`), as
    canonical JSON (the key's part): however the model groups its fields, each enters the key
    by its own name, and `ModelParams` reads the flat form back."""
    return canonical(leaf_values(params or ModelParams()))


def spec_json(spec: RunSpec) -> str:
    """The spec's non-default fields, as canonical JSON (the key's part)."""
    return canonical(spec.model_dump(mode="json", exclude_defaults=True))


def params_hash(params: ModelParams | None) -> str:
    """12 hex digits of the non-default parameters' hash (`params_json`): the defaults hash
    alike however they are spelled, any changed parameter (the ground included) differs."""
    return hashlib.sha256(params_json(params).encode()).hexdigest()[:12]


def provenance(params: ModelParams | None, dt_s: float | None = None) -> dict[str, Any]:
    """What made a run's numbers, for a file's header or columns: the physics' version
    (`PHYSICS_VERSION`), the parameters' hash, the ground and the physics step (`dt_s`, s;
    None: the parameters' own)."""
    p = params or ModelParams()
    return {
        "physics_version": PHYSICS_VERSION,
        "params_hash": params_hash(p),
        "ground": p.contact.ground,
        "dt_s": p.numerics.dt if dt_s is None else dt_s,
    }

"""What the service is and runs: health, the model parameters."""

from __future__ import annotations

import math
from typing import Any

from fastapi import APIRouter, HTTPException

from server.deps import PoolDep, SettingsDep, StoreDep
from server.schemas import Health, ModelParameter, Problem, WorkerHealth

router = APIRouter(tags=["meta"])


def _plain(v: Any) -> Any:
    """parameter_table values may be numpy scalars; JSON wants plain Python."""
    if hasattr(v, "item"):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


@router.get(
    "/v1/model",
    response_model=list[ModelParameter],
    responses={503: {"model": Problem, "description": "the simulation core is unavailable"}},
    summary="The model parameters in use, with their origin (paper or invented)",
)
def get_model() -> Any:
    try:
        from sim_core import parameter_table
    except Exception as exc:
        raise HTTPException(
            status_code=503, detail=f"sim_core could not be imported: {exc}"
        ) from exc
    return [
        {"name": n, "value": _plain(v), "origin": o, "reason": r}
        for n, v, o, r in parameter_table()
    ]


@router.get("/healthz", response_model=Health)
def healthz(store: StoreDep, pool: PoolDep, settings: SettingsDep) -> Any:
    counts = store.counts()
    stats = pool.stats()
    ok = stats.alive == stats.configured
    return {
        "status": "ok" if ok else "degraded",
        "workers": WorkerHealth(configured=stats.configured, alive=stats.alive, busy=stats.busy),
        "queued": counts["queued"],
        "running": counts["running"],
        "queue_limit": settings.queue_limit,
    }

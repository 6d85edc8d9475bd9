"""What the service is and runs: health, the model parameters."""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any

import fastapi_offline
from fastapi import APIRouter, Request
from fastapi.openapi.docs import (
    get_redoc_html,
    get_swagger_ui_html,
    get_swagger_ui_oauth2_redirect_html,
)
from fastapi.responses import HTMLResponse, Response

from server.deps import PoolDep, SettingsDep, StoreDep
from server.schemas import (
    Health,
    IntegratorInfo,
    ModelParameter,
    WorkerHealth,
)
from server.status import JobStatus
from sim_core.contract import (
    DEFAULT_DT_S,
    DEFAULT_INTEGRATOR,
    INTEGRATORS,
    MAX_STABLE_DT_S,
    parameter_table,
)

router = APIRouter(tags=["meta"])

# Swagger UI and ReDoc from the installed fastapi-offline package, never from a CDN: the
# service is used in labs without internet. create_app mounts this folder at DOCS_ASSETS.
DOCS_STATIC = Path(fastapi_offline.__file__).parent / "static"
DOCS_ASSETS = "/docs-assets"
# ReDoc's bundle still fetches its "API docs by Redocly" logo from a CDN; served with that
# one address replaced by an inline (empty) image, nothing on /redoc leaves this server.
REDOC_CDN_LOGO = b"https://cdn.redoc.ly/redoc/logo-mini.svg"
INLINE_LOGO = b"data:image/svg+xml,%3Csvg xmlns='http://www.w3.org/2000/svg'/%3E"


@functools.cache
def offline_redoc_bundle() -> bytes:
    return (DOCS_STATIC / "redoc.standalone.js").read_bytes().replace(REDOC_CDN_LOGO, INLINE_LOGO)


@router.get(f"{DOCS_ASSETS}/redoc.standalone.js", include_in_schema=False)
def redoc_bundle() -> Response:
    return Response(offline_redoc_bundle(), media_type="text/javascript")


@router.get("/docs", include_in_schema=False)
def swagger_ui(request: Request) -> HTMLResponse:
    root = request.scope.get("root_path", "")
    return get_swagger_ui_html(
        openapi_url=f"{root}{request.app.openapi_url}",
        title=f"{request.app.title} - Swagger UI",
        oauth2_redirect_url=f"{root}/docs/oauth2-redirect",
        swagger_js_url=f"{root}{DOCS_ASSETS}/swagger-ui-bundle.js",
        swagger_css_url=f"{root}{DOCS_ASSETS}/swagger-ui.css",
        swagger_favicon_url=f"{root}{DOCS_ASSETS}/favicon.png",
        # no validator badge: it sends the spec's address to validator.swagger.io
        swagger_ui_parameters={"validatorUrl": None},
    )


@router.get("/docs/oauth2-redirect", include_in_schema=False)
def swagger_ui_redirect() -> HTMLResponse:
    return get_swagger_ui_oauth2_redirect_html()


@router.get("/redoc", include_in_schema=False)
def redoc(request: Request) -> HTMLResponse:
    root = request.scope.get("root_path", "")
    return get_redoc_html(
        openapi_url=f"{root}{request.app.openapi_url}",
        title=f"{request.app.title} - ReDoc",
        redoc_js_url=f"{root}{DOCS_ASSETS}/redoc.standalone.js",
        redoc_favicon_url=f"{root}{DOCS_ASSETS}/favicon.png",
        with_google_fonts=False,
    )


@router.get(
    "/v1/integrators",
    response_model=list[IntegratorInfo],
    summary="The integrators a job may ask for, with the largest stable timestep of each",
)
def list_integrators() -> Any:
    return [
        {
            "name": name,
            "default": name == DEFAULT_INTEGRATOR,
            "default_dt_s": DEFAULT_DT_S if name == DEFAULT_INTEGRATOR else None,
            "max_stable_dt_s": MAX_STABLE_DT_S[name],
        }
        for name in INTEGRATORS
    ]


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
    summary="The model parameters in use, with their origin (paper or invented)",
)
def get_model() -> Any:
    return [row._asdict() | {"value": _plain(row.value)} for row in parameter_table()]


@router.get("/healthz", response_model=Health)
def healthz(store: StoreDep, pool: PoolDep, settings: SettingsDep) -> Any:
    counts = store.counts()
    stats = pool.stats()
    ok = stats.alive == stats.configured
    return {
        "status": "ok" if ok else "degraded",
        "workers": WorkerHealth(configured=stats.configured, alive=stats.alive, busy=stats.busy),
        "queued": counts[JobStatus.QUEUED],
        "running": counts[JobStatus.RUNNING],
        "queue_limit": settings.queue_limit,
    }

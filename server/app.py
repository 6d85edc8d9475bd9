"""The FastAPI application: create_app builds it, the lifespan owns the store and the workers.

Routes live in `server/routes/` (one module per resource), their dependencies in
`server/deps.py`; this module wires them together with the error handlers.
"""

from __future__ import annotations

import fcntl
import json
import logging
import threading
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

from fastapi import Depends, FastAPI, Request
from fastapi.exception_handlers import http_exception_handler
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from fastapi.staticfiles import StaticFiles
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import Match

from server.deps import R401, require_token
from server.errors import content_type_error, humanize, method_not_allowed
from server.jobs import JobStore
from server.kinds import ComputeSettings
from server.routes import jobs, meta
from server.settings import Settings
from server.workers import WorkerPool

log = logging.getLogger("insect_gait.server")


class InstanceLock:
    """One API process per database: the restart recovery assumes no other server's workers
    are running jobs from the same file. flock is released by the kernel on kill -9."""

    def __init__(self, db_path: str) -> None:
        self.path = f"{db_path}.lock"
        self._fd: Any = None

    def acquire(self) -> None:
        self._fd = open(self.path, "a+")  # held for the server's lifetime
        try:
            fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            self._fd.close()
            raise RuntimeError(
                f"another insect-gait api already serves {self.path[:-5]}; "
                "stop it or give this one another --db"
            ) from None

    def probe(self) -> None:
        """Raise the same RuntimeError as `acquire` if another server holds the lock; hold
        nothing afterwards (the app's lifespan takes it for real)."""
        self.acquire()
        self.release()

    def release(self) -> None:
        if self._fd is not None:
            fcntl.flock(self._fd, fcntl.LOCK_UN)
            self._fd.close()
            self._fd = None


def create_app(settings: Settings | None = None) -> FastAPI:
    """Build the app; the store and the workers start in its lifespan, not at import."""
    settings = settings or Settings()
    store = JobStore(settings.db_path)
    pool = WorkerPool(
        store=store,
        db_path=settings.db_path,
        size=settings.workers,
        nthread=settings.threads_for_one_worker(),
        niceness=settings.worker_nice,
        where=ComputeSettings(
            cache_dir=settings.cache_dir,
            cache_max_bytes=settings.cache_max_bytes,
            dask_address=settings.dask_address,
        ),
    )
    retention = Retention(store, settings)

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        settings.db_path.parent.mkdir(parents=True, exist_ok=True)
        lock = InstanceLock(str(settings.db_path))
        lock.acquire()
        try:
            store.init()
            requeued, failed = store.recover_interrupted(settings.max_requeues)
            if requeued or failed:
                log.warning(
                    "recovered after an unclean stop: %d job(s) re-queued, %d failed",
                    len(requeued),
                    len(failed),
                )
            retention.start()
            if settings.workers > 0:
                pool.start()
            yield
        finally:
            retention.stop()
            if settings.workers > 0:
                pool.stop()
            store.close()
            lock.release()

    app = FastAPI(
        title="insect-gait API",
        version="1",
        description="Queue hexapod simulations (Fujiki et al. 2013 model), poll them, fetch "
        "results. Mutating endpoints need `Authorization: Bearer <token>` when the server "
        "has a token configured.",
        lifespan=lifespan,
        docs_url=None,  # served by routes/meta.py from local assets, not a CDN
        redoc_url=None,
    )
    app.state.settings = settings
    app.state.store = store
    app.state.pool = pool

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError) -> JSONResponse:
        if isinstance(exc.body, bytes | bytearray):
            # FastAPI parses JSON only when the Content-Type says JSON (or is missing)
            wrong = content_type_error(request.headers.get("content-type"))
            if wrong is not None:
                return JSONResponse(status_code=422, content={"detail": [wrong]})
        return JSONResponse(status_code=422, content={"detail": humanize(exc.errors(), exc.body)})

    @app.exception_handler(StarletteHTTPException)
    async def _http(request: Request, exc: StarletteHTTPException) -> Any:
        if exc.status_code == 400 and exc.detail == "There was an error parsing the body":
            why = parse_failure(await request.body())
            return JSONResponse(status_code=400, content={"detail": why})
        if exc.status_code == 405:  # every method the path takes (Starlette names one route's)
            methods = [
                m for m in ("GET", "POST", "PUT", "PATCH", "DELETE")
                if any(r.matches(dict(request.scope, method=m))[0] == Match.FULL
                       for r in request.app.router.routes)
            ]  # fmt: skip
            detail = method_not_allowed(request.method, request.url.path, methods)
            return JSONResponse(status_code=405, content={"detail": detail},
                                headers={"Allow": ", ".join(methods)})  # fmt: skip
        return await http_exception_handler(request, exc)

    # The token check is declared only when a token is configured, so the OpenAPI document
    # says what is true; it is still the one `require_token` (overridable) either way.
    token = settings.api_token is not None
    app.include_router(jobs.router)
    app.include_router(
        jobs.write_router,
        dependencies=[Depends(require_token)] if token else [],
        responses=R401 if token else {},
    )
    app.include_router(meta.router)
    # after the routers: meta serves one asset itself (ReDoc's bundle, made offline)
    app.mount(meta.DOCS_ASSETS, StaticFiles(directory=meta.DOCS_STATIC), name="docs-assets")
    return app


def parse_failure(raw: bytes) -> str:
    """Why a body FastAPI could not parse was refused, in words a person can act on."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        return (
            f"the request body is not valid UTF-8 (byte 0x{raw[exc.start]:02x} at offset "
            f"{exc.start}); send the JSON job spec encoded as UTF-8"
        )
    try:
        json.loads(text)
    except RecursionError:
        return "the request body's JSON is nested too deeply; a job spec is a flat object"
    except ValueError as exc:
        if "digits" in str(exc):
            return (
                "a number in the request body has more than 4300 digits, more than can be "
                "read; send numbers with fewer digits"
            )
        return f"the request body could not be parsed: {exc}"
    return "the request body could not be parsed"


class Retention:
    """Applies the retention settings (retention_days, retention_count) to finished jobs at
    start-up and every retention_interval_s, in a thread of the API process; and forgets
    idempotency keys past idempotency_ttl_s and tombstones past tombstone_days (a lookup
    ignores expired ones anyway: this keeps the tables small)."""

    def __init__(self, store: JobStore, settings: Settings) -> None:
        self.store = store
        self.settings = settings
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    @property
    def enabled(self) -> bool:
        s = self.settings
        return s.retention_days is not None or s.retention_count is not None

    def apply(self) -> int:
        s = self.settings
        n = self.store.purge_finished(s.retention_days, s.retention_count) if self.enabled else 0
        if n:
            log.info("retention: deleted %d finished job(s)", n)
        self.store.forget_expired(s.idempotency_ttl_s, s.tombstone_days)
        return n

    def start(self) -> None:
        self.apply()
        self._thread = threading.Thread(target=self._run, name="job-retention", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(self.settings.retention_interval_s):
            try:
                self.apply()
            except Exception:  # a locked or broken database must not end the loop
                log.exception("retention failed")
        self.store.close()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(10)

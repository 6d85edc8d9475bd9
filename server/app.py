"""The FastAPI application: create_app builds it, the lifespan owns the store and the workers.

Routes live in `server/routes/` (one module per resource), their dependencies in
`server/deps.py`; this module wires them together with the error handlers.
"""

from __future__ import annotations

import fcntl
import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

from fastapi import Depends, FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse

from server.deps import R401, require_token
from server.errors import humanize
from server.jobs import JobStore
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
    )

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
            if settings.workers > 0:
                pool.start()
            yield
        finally:
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
    )
    app.state.settings = settings
    app.state.store = store
    app.state.pool = pool

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError) -> JSONResponse:
        return JSONResponse(status_code=422, content={"detail": humanize(exc.errors(), exc.body)})

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
    return app

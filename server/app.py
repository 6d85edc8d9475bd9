"""The FastAPI application: routes, auth and the lifespan that owns the store and the workers.

Routes are plain `def` functions: FastAPI runs them in its thread pool, so a SQLite read or a
figure never blocks the event loop. No route simulates; jobs go to the worker pool.
"""

from __future__ import annotations

import fcntl
import logging
import math
import secrets
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Annotated, Any, Literal

from fastapi import Depends, FastAPI, HTTPException, Path, Query, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse, Response
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from server import figures
from server.errors import humanize, limit_error
from server.jobs import JobStore, QueueFull
from server.schemas import (
    FINISHED,
    Health,
    Job,
    JobPage,
    JobSpec,
    JobStatus,
    ModelParameter,
    Problem,
    ValidationProblem,
    WorkerHealth,
)
from server.settings import Settings
from server.workers import WorkerPool

log = logging.getLogger("insect_gait.server")

JobId = Annotated[str, Path(min_length=1, max_length=64, description="job id from POST /v1/jobs")]
_bearer = HTTPBearer(auto_error=False, description="needed only when INSECT_GAIT_API_TOKEN is set")

Responses = dict[int | str, dict[str, Any]]


def _resp(code: int, model: type, description: str) -> Responses:
    return {code: {"model": model, "description": description}}


R401 = _resp(401, Problem, "API token missing or wrong")
R404 = _resp(404, Problem, "no such job")
R409 = _resp(409, Problem, "the job is not in a state that allows this")
R422 = _resp(422, ValidationProblem, "invalid input; the message names field and range")


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


def _job_out(job: dict[str, Any]) -> dict[str, Any]:
    base = f"/v1/jobs/{job['id']}"
    return {
        **job,
        "links": {"self": base, "result": f"{base}/result", "figure": f"{base}/figure.png"},
    }


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

    def require_token(
        creds: Annotated[HTTPAuthorizationCredentials | None, Depends(_bearer)],
    ) -> None:
        token = settings.api_token
        if token is None:
            return
        given = creds.credentials if creds is not None else ""
        if (
            creds is None
            or creds.scheme.lower() != "bearer"
            or not secrets.compare_digest(given.encode(), token.get_secret_value().encode())
        ):
            raise HTTPException(
                status_code=401,
                detail="this server needs 'Authorization: Bearer <token>' for this request",
                headers={"WWW-Authenticate": "Bearer"},
            )

    # Declared only when a token is configured, so the OpenAPI document says what is true.
    auth = [Depends(require_token)] if settings.api_token is not None else []
    r401 = R401 if settings.api_token is not None else {}

    def get_job_or_404(job_id: str) -> dict[str, Any]:
        job = store.get(job_id)
        if job is None:
            raise HTTPException(status_code=404, detail=f"no job with id {job_id!r}")
        return job

    def require_done(job: dict[str, Any]) -> None:
        if job["status"] != "done":
            why = f": {job['error']}" if job.get("error") else ""
            raise HTTPException(
                status_code=409,
                detail=f"job {job['id']} is {job['status']}, results exist only for done jobs{why}",
            )

    @app.post(
        "/v1/jobs",
        status_code=202,
        response_model=Job,
        responses={
            **r401,
            **R422,
            429: {"model": Problem, "description": "queue full; see Retry-After"},
        },
        summary="Queue a simulation job",
        dependencies=auth,
    )
    def submit_job(spec: JobSpec, response: Response) -> Any:
        problems = []
        runs = spec.run_count()
        if runs > settings.max_runs_per_job:
            problems.append(
                limit_error(
                    "d31_init",
                    f"the job asks for {runs} simulations",
                    f"at most {settings.max_runs_per_job} simulations per job "
                    "(max_runs_per_job; sweeps count len(d31_init) x beta_range.steps)",
                )
            )
        total = spec.total_sim_seconds()
        if total > settings.max_job_sim_seconds:
            problems.append(
                limit_error(
                    "duration_s",
                    f"the job asks for {total:g} simulated seconds in all "
                    f"({runs} runs x {spec.duration_s:g} s)",
                    f"at most {settings.max_job_sim_seconds:g} simulated seconds per job "
                    "(max_job_sim_seconds); split it into several jobs",
                )
            )
        if problems:
            return JSONResponse(status_code=422, content={"detail": problems})
        out = store.submit(spec.kind, spec.model_dump(mode="json"), total, settings.queue_limit)
        if isinstance(out, QueueFull):
            retry = _retry_after(store, settings, out.queued)
            return JSONResponse(
                status_code=429,
                headers={"Retry-After": str(retry)},
                content={
                    "detail": f"the queue is full ({out.queued} queued jobs, queue_limit = "
                    f"{settings.queue_limit}); retry in about {retry} s"
                },
            )
        pool.wake()
        response.headers["Location"] = f"/v1/jobs/{out['id']}"
        return _job_out(out)

    @app.get("/v1/jobs", response_model=JobPage, responses=R422, summary="List jobs, newest first")
    def list_jobs(
        status: Annotated[JobStatus | None, Query(description="only jobs in this state")] = None,
        limit: Annotated[int, Query(ge=1, le=200)] = 50,
        offset: Annotated[int, Query(ge=0, le=1_000_000_000)] = 0,
    ) -> Any:
        items, total = store.list_jobs(status, limit, offset)
        return {
            "items": [_job_out(j) for j in items],
            "total": total,
            "limit": limit,
            "offset": offset,
        }

    @app.get("/v1/jobs/{job_id}", response_model=Job, responses={**R404, **R422})
    def get_job(job_id: JobId) -> Any:
        return _job_out(get_job_or_404(job_id))

    @app.get(
        "/v1/jobs/{job_id}/result",
        responses={
            200: {
                "description": "the result as JSON, or CSV with ?format=csv",
                "content": {"application/json": {}, "text/csv": {}},
            },
            **R404,
            **R409,
            **R422,
        },
        summary="Result of a done job",
    )
    def get_result(
        job_id: JobId,
        format: Annotated[Literal["json", "csv"], Query(description="json or csv")] = "json",
    ) -> Response:
        job = get_job_or_404(job_id)
        require_done(job)
        result = store.result(job_id)
        if result is None:
            raise HTTPException(status_code=409, detail=f"job {job_id} has no stored result")
        if format == "csv":
            return Response(
                figures.records_csv(result.get("records", [])),
                media_type="text/csv",
                headers={"Content-Disposition": f'attachment; filename="{job_id}.csv"'},
            )
        return JSONResponse({"job_id": job_id, "kind": job["kind"], "result": result})

    @app.get(
        "/v1/jobs/{job_id}/figure.png",
        responses={
            200: {"description": "PNG figure", "content": {"image/png": {}}},
            **R404,
            **R409,
            **R422,
        },
        response_class=Response,
        summary="Figure of a done job",
    )
    def get_figure(job_id: JobId) -> Response:
        job = get_job_or_404(job_id)
        require_done(job)
        result = store.result(job_id)
        if result is None:
            raise HTTPException(status_code=409, detail=f"job {job_id} has no stored result")
        return Response(figures.figure_png(job, result), media_type="image/png")

    @app.delete(
        "/v1/jobs/{job_id}",
        response_model=Job,
        responses={**r401, **R404, **R409, **R422},
        summary="Cancel a queued or running job (a running one is stopped)",
        dependencies=auth,
    )
    def cancel_job(job_id: JobId) -> Any:
        previous, job = store.cancel(job_id)
        if job is None:
            raise HTTPException(status_code=404, detail=f"no job with id {job_id!r}")
        if previous in FINISHED and previous != "cancelled":
            raise HTTPException(
                status_code=409, detail=f"job {job_id} is already {previous}; nothing to cancel"
            )
        pool.wake()
        return _job_out(job)

    @app.get(
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

    @app.get("/healthz", response_model=Health)
    def healthz() -> Any:
        counts = store.counts()
        stats = pool.stats()
        ok = stats.alive == stats.configured
        return {
            "status": "ok" if ok else "degraded",
            "workers": WorkerHealth(
                configured=stats.configured, alive=stats.alive, busy=stats.busy
            ),
            "queued": counts["queued"],
            "running": counts["running"],
            "queue_limit": settings.queue_limit,
        }

    return app


def _plain(v: Any) -> Any:
    """parameter_table values may be numpy scalars; JSON wants plain Python."""
    if hasattr(v, "item"):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def _retry_after(store: JobStore, settings: Settings, queued: int) -> int:
    """Seconds until a queue slot likely frees: one of the busy workers finishing a job."""
    if settings.workers == 0:
        return 60  # nothing drains this queue; ask again in a minute
    typical = store.typical_job_seconds() or 5.0
    return int(min(600, max(1, math.ceil(typical / settings.workers))))

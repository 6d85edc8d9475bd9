"""/v1/jobs: queue, list, poll, fetch results and figures, cancel.

Routes are plain `def` functions: FastAPI runs them in its thread pool, so a SQLite read or a
figure never blocks the event loop. No route simulates; jobs go to the worker pool.
`router` holds the reads, `write_router` the mutations (the app adds the token check to it
when a token is configured, so the OpenAPI document says what is true).
"""

from __future__ import annotations

import logging
from datetime import UTC, datetime
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Header, HTTPException, Query, Response
from fastapi.responses import JSONResponse
from pydantic import ValidationError

from server import figures, ledger
from server.deps import (
    R400,
    R404,
    R409,
    R410,
    R422,
    JobDep,
    JobId,
    PoolDep,
    SettingsDep,
    StoreDep,
    get_job_or_404,
    no_such_job,
)
from server.errors import limit_error, sanitize
from server.estimates import eta_of, retry_after_s, wall_per_sim_second
from server.jobs import IdempotencyKey, JobRow, JobStore, KeyConflict, QueueFull, Replayed
from server.kinds import KINDS, RECORD_COLUMNS, JobSpec
from server.kinds.provenance import stamped
from server.schemas import Job, JobLinks, JobPage, JobResult, Problem
from server.settings import Settings
from server.status import FINISHED, JobStatus, StatusValue
from sim_core.contract import DEFAULT_DT_S

log = logging.getLogger(__name__)
router = APIRouter(prefix="/v1/jobs", tags=["jobs"])
write_router = APIRouter(prefix="/v1/jobs", tags=["jobs"])


def job_out(job: JobRow, store: JobStore | None = None) -> Job:
    """A stored job as the API shows it: links, an estimated time left while it runs, and an
    error message cleaned of anything internal (rows written by older servers included)."""
    base = f"/v1/jobs/{job.id}"
    eta = None
    if job.status is JobStatus.RUNNING and store is not None:
        eta = eta_of(job, datetime.now(UTC), wall_per_sim_second(store.recent_done()))
    return Job(
        id=job.id,
        kind=job.kind,
        status=job.status.value,
        progress=job.progress,
        created_at=job.created_at,
        started_at=job.started_at,
        finished_at=job.finished_at,
        error=sanitize(job.error) if job.error else job.error,
        note=job.note,
        attempts=job.attempts,
        requeues=job.requeues,
        sim_seconds=job.sim_seconds,
        simulations=job.simulations,
        eta_s=eta,
        spec=job.spec,
        links=JobLinks(self=base, result=f"{base}/result", figure=f"{base}/figure.png"),
    )


def require_done(job: JobRow) -> None:
    if job.status is not JobStatus.DONE:
        why = f": {sanitize(job.error)}" if job.error else ""
        raise HTTPException(
            status_code=409,
            detail=f"job {job.id} is {job.status}, results exist only for done jobs{why}",
        )


def key_issue(msg: str) -> dict[str, Any]:
    """A 422 item about the Idempotency-Key header, in the shape of the others."""
    return {"loc": ["header", "Idempotency-Key"], "field": "Idempotency-Key",
            "msg": f"Idempotency-Key: {msg}", "type": "idempotency_key"}  # fmt: skip


def resp_410_key() -> dict[int | str, dict[str, Any]]:
    return {410: {"model": Problem, "description": "the Idempotency-Key queued a job that has "
                  "since been deleted (the message says when and why)"}}  # fmt: skip


def retry_after(store: JobStore, settings: Settings) -> int:
    """Seconds until a queue slot likely frees: the soonest running job's estimated end."""
    now = datetime.now(UTC)
    rate = wall_per_sim_second(store.recent_done())
    left = [eta_of(j, now, rate) for j in store.running_jobs()]
    return retry_after_s(
        workers=settings.workers, running_remaining_s=[x for x in left if x is not None]
    )


@write_router.post(
    "",
    status_code=202,
    response_model=Job,
    responses={
        **R400,
        **resp_410_key(),
        **R422,
        429: {"model": Problem, "description": "queue full; see Retry-After"},
    },
    summary="Queue a simulation job",
)
def submit_job(
    spec: JobSpec,
    response: Response,
    store: StoreDep,
    pool: PoolDep,
    settings: SettingsDep,
    idempotency_key: Annotated[
        str | None,
        Header(
            alias="Idempotency-Key",
            description="any unique string (a UUID): a POST repeated with the same key and "
            "body within idempotency_ttl_s returns the job the first one queued (202, header "
            "Idempotent-Replayed: true) instead of queueing a second; the same key with "
            "another body is refused (422)",
        ),
    ] = None,
) -> Any:
    key = None
    if idempotency_key is not None:
        problem = ledger.key_problem(idempotency_key)
        if problem:
            return JSONResponse(status_code=422, content={"detail": [key_issue(problem)]})
        digest = ledger.body_hash(spec.model_dump(mode="json"))  # its `kind` included
        key = IdempotencyKey(idempotency_key, digest, settings.idempotency_ttl_s)
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
    size = spec.size_sim_seconds()
    if size > settings.max_job_sim_seconds:
        finer = (
            f" at dt_s {spec.effective_dt_s():g} s, as many physics steps as {size:g} s at the "
            f"default {DEFAULT_DT_S:g} s"
            if size > total
            else ""
        )
        problems.append(
            limit_error(
                "duration_s",
                f"the job asks for {total:g} simulated seconds in all "
                f"({runs} runs x {spec.sim_seconds_per_run():g} s){finer}",
                f"at most {settings.max_job_sim_seconds:g} simulated seconds per job at the "
                "default step, a finer step counting as that many more (max_job_sim_seconds); "
                "split it into several jobs",
            )
        )
    cost = spec.cost_problem()  # the core's rule: steps per run, memory of all runs at once
    if cost is not None:
        problems.append(
            limit_error(
                "d31_init",
                cost,
                "the core's cost bounds (sim_core.contract: MIN_DT_S, MAX_STEPS_PER_RUN, "
                "MAX_JOB_BYTES)",
            )
        )
    if problems:
        return JSONResponse(status_code=422, content={"detail": problems})
    out = store.submit(
        spec.kind_name(), spec.model_dump(mode="json"), total, settings.queue_limit, key
    )
    if isinstance(out, KeyConflict):
        return JSONResponse(status_code=422, content={"detail": [key_issue(
            f"this Idempotency-Key was sent at {out.key_created_at} with another job spec "
            f"(it queued job {out.job_id}); a key names one request: send a new key for a new "
            "job, or the same spec to get that job back")]})  # fmt: skip
    if isinstance(out, Replayed):
        if out.job is None:
            gone = out.gone.sentence() if out.gone else "its job no longer exists"
            raise HTTPException(status_code=410, detail=f"this Idempotency-Key queued a job "
                                f"at {out.key_created_at}, since deleted: {gone}")  # fmt: skip
        response.headers["Location"] = f"/v1/jobs/{out.job.id}"
        response.headers["Idempotent-Replayed"] = "true"
        return job_out(out.job, store)
    if isinstance(out, QueueFull):
        retry = retry_after(store, settings)
        return JSONResponse(
            status_code=429,
            headers={"Retry-After": str(retry)},
            content={
                "detail": f"the queue is full ({out.queued} queued jobs, queue_limit = "
                f"{settings.queue_limit}); retry in about {retry} s"
            },
        )
    pool.wake()
    response.headers["Location"] = f"/v1/jobs/{out.id}"
    return job_out(out, store)


@router.get("", response_model=JobPage, responses=R422, summary="List jobs, newest first")
def list_jobs(
    store: StoreDep,
    status: Annotated[StatusValue | None, Query(description="only jobs in this state")] = None,
    limit: Annotated[int, Query(ge=1, le=200)] = 50,
    offset: Annotated[int, Query(ge=0, le=1_000_000_000)] = 0,
) -> Any:
    items, total = store.list_jobs(JobStatus(status) if status else None, limit, offset)
    return {
        "items": [job_out(j, store) for j in items],
        "total": total,
        "limit": limit,
        "offset": offset,
    }


@router.get("/{job_id}", response_model=Job, responses={**R404, **R410, **R422})
def get_job(job: JobDep, store: StoreDep) -> Any:
    return job_out(job, store)


@router.get(
    "/{job_id}/result",
    response_model=JobResult,
    # the keys the stored result has, no more: a table the job did not keep (a null at the top
    # level is not stored) and a measure added after the result was stored stay absent
    response_model_exclude_unset=True,
    responses={
        200: {
            "description": "the result as JSON (its kind's result model, validated on the way "
            "out), or CSV with ?format=csv (`table` picks which)",
            "content": {"text/csv": {}},
        },
        **R404,
        **R409,
        **R410,
        **R422,
    },
    summary="Result of a done job",
)
def get_result(
    job_id: JobId,
    store: StoreDep,
    settings: SettingsDep,
    format: Annotated[Literal["json", "csv"], Query(description="json or csv")] = "json",
    table: Annotated[
        Literal["records", "d31", "samples"],
        Query(
            description="CSV only: `records` (one summary row per run or grid point, the "
            "default), or, for run jobs with include_series, `d31` (Delta31 at every leg-1 "
            "touchdown) or `samples` (every recorded sample: stance per leg, body position)"
        ),
    ] = "records",
) -> Any:
    # looked up here, not as a dependency: a bad query parameter is a 422 before a 404
    job = get_job_or_404(job_id, store, settings)
    require_done(job)
    result = store.result(job_id)
    if result is None:
        raise HTTPException(status_code=409, detail=f"job {job_id} has no stored result")
    if format == "csv":
        if table == "records":
            rows, columns = result.get("records", []), RECORD_COLUMNS.get(job.kind, ())
        elif table in (series := result.get("series") or {}) and job.kind in KINDS:
            rows, columns = series[table], KINDS[job.kind].table_columns(table)
        else:
            raise HTTPException(
                status_code=409,
                detail=f"job {job_id} has no time series (table={table!r} needs a run job "
                "submitted with include_series: true)",
            )
        name = job_id if table == "records" else f"{job_id}-{table}"
        rows, columns = stamped(rows, columns, result.get("provenance"))
        return Response(
            figures.records_csv(rows, columns),
            media_type="text/csv",
            headers={"Content-Disposition": f'attachment; filename="{name}.csv"'},
        )
    return served_result(job_id, job.kind, result)


def served_result(job_id: str, kind: str, result: dict[str, Any]) -> Any:
    """A stored result as GET .../result serves it: validated against its kind's result model
    (`JobResult`, which the route's response model validates again as it writes it). Stored
    results are read leniently, not migrated: a field added since (a new measure) may be
    absent and stays absent; a result that no longer fits its model at all (a field renamed or
    removed since it was stored) is served as stored, with `X-Result-Schema: unvalidated`
    and a warning in the log, rather than refused: it is still the job's data."""
    body = {"job_id": job_id, "kind": kind, "result": result}
    try:
        return JobResult.model_validate(body)
    except ValidationError as exc:
        log.warning("job %s: stored result does not fit its model (%d errors); served as "
                    "stored", job_id, exc.error_count())  # fmt: skip
        return JSONResponse(body, headers={"X-Result-Schema": "unvalidated"})


@router.get(
    "/{job_id}/figure.png",
    responses={
        200: {"description": "PNG figure", "content": {"image/png": {}}},
        **R404,
        **R409,
        **R410,
        **R422,
    },
    response_class=Response,
    summary="Figure of a done job",
)
def get_figure(job_id: JobId, store: StoreDep, settings: SettingsDep) -> Response:
    job = get_job_or_404(job_id, store, settings)
    require_done(job)
    result = store.result(job_id)
    if result is None:
        raise HTTPException(status_code=409, detail=f"job {job_id} has no stored result")
    return Response(figures.figure_png(job.kind, job.spec, result), media_type="image/png")


@write_router.delete(
    "/{job_id}",
    response_model=Job,
    responses={**R404, **R409, **R410, **R422},
    summary="Cancel a queued or running job; with ?purge=true delete a finished one",
)
def delete_job(
    job_id: JobId,
    store: StoreDep,
    pool: PoolDep,
    settings: SettingsDep,
    purge: Annotated[
        bool,
        Query(
            description="delete a finished (done, failed, cancelled) job and its result; "
            "without it DELETE only cancels, so a retried cancel never deletes a record"
        ),
    ] = False,
) -> Any:
    if purge:
        status, gone = store.delete_finished(job_id)
        if gone is None:
            raise no_such_job(job_id, store, settings)
        if status not in FINISHED:
            raise HTTPException(
                status_code=409,
                detail=f"job {job_id} is {status}; cancel it first (DELETE without purge), "
                "then purge it",
            )
        return job_out(gone)
    previous, job = store.cancel(job_id)
    if job is None:
        raise no_such_job(job_id, store, settings)
    if previous in FINISHED and previous is not JobStatus.CANCELLED:
        raise HTTPException(
            status_code=409,
            detail=f"job {job_id} is already {previous}; nothing to cancel (to delete it and "
            f"its result: DELETE /v1/jobs/{job_id}?purge=true)",
        )
    pool.wake()
    return job_out(job, store)

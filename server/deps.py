"""Dependencies, declared once: the settings, the job store, the worker pool and the token check.

Routes take them as `Annotated` types (`store: StoreDep`), as the FastAPI full-stack template
does, so a test or a deployment can swap any of them through `app.dependency_overrides`
(e.g. `app.dependency_overrides[get_store] = lambda: other_store`).
"""

from __future__ import annotations

import secrets
from typing import Annotated, Any

from fastapi import Depends, HTTPException, Path, Request
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from server.jobs import JobRow, JobStore
from server.schemas import Problem, ValidationProblem
from server.settings import Settings
from server.workers import WorkerPool

bearer = HTTPBearer(auto_error=False, description="needed only when INSECT_GAIT_API_TOKEN is set")

Responses = dict[int | str, dict[str, Any]]


def resp(code: int, model: type, description: str) -> Responses:
    return {code: {"model": model, "description": description}}


R400 = resp(
    400,
    Problem,
    "the body could not be parsed (not UTF-8, a number over 4300 digits, JSON nested too "
    "deeply); the message says which",
)
R401 = resp(401, Problem, "API token missing, malformed or wrong; the message says which")
R404 = resp(404, Problem, "no such job")
R410 = resp(
    410,
    Problem,
    "the job was deleted (by retention or a purge): the message says when and why; its id "
    "answers so for tombstone_days, then 404",
)
R409 = resp(409, Problem, "the job is not in a state that allows this")
R422 = resp(422, ValidationProblem, "invalid input; the message names field and range")


def get_settings(request: Request) -> Settings:
    settings: Settings = request.app.state.settings
    return settings


def get_store(request: Request) -> JobStore:
    store: JobStore = request.app.state.store
    return store


def get_pool(request: Request) -> WorkerPool:
    pool: WorkerPool = request.app.state.pool
    return pool


SettingsDep = Annotated[Settings, Depends(get_settings)]
StoreDep = Annotated[JobStore, Depends(get_store)]
PoolDep = Annotated[WorkerPool, Depends(get_pool)]


def require_token(
    request: Request,
    settings: SettingsDep,
    creds: Annotated[HTTPAuthorizationCredentials | None, Depends(bearer)],
) -> None:
    """401 unless the request carries the configured token (no token configured: open). The
    message says which of three things went wrong: no Authorization header, one that is not
    'Bearer <token>', or a token that is not this server's."""
    token = settings.api_token
    if token is None:
        return
    header = request.headers.get("authorization")
    if header is None:
        why = (
            "this server needs a token for this request: send the header "
            "'Authorization: Bearer <token>' (none was sent)"
        )
    elif creds is None or creds.scheme.lower() != "bearer":
        why = (
            "the Authorization header is not of the form 'Bearer <token>'; send "
            "'Authorization: Bearer <token>'"
        )
    elif not secrets.compare_digest(creds.credentials.encode(), token.get_secret_value().encode()):
        why = "the token sent in 'Authorization: Bearer ...' is not this server's token"
    else:
        return
    raise HTTPException(status_code=401, detail=why, headers={"WWW-Authenticate": "Bearer"})


TokenDep = Annotated[None, Depends(require_token)]

JobId = Annotated[str, Path(min_length=1, max_length=64, description="job id from POST /v1/jobs")]


def no_such_job(job_id: str, store: JobStore, settings: Settings) -> HTTPException:
    """410 Gone saying when and why, for a job deleted not longer than tombstone_days ago;
    else 404."""
    gone = store.gone(job_id, settings.tombstone_days)
    if gone is not None:
        return HTTPException(status_code=410, detail=gone.sentence())
    return HTTPException(status_code=404, detail=f"no job with id {job_id!r}")


def get_job_or_404(job_id: JobId, store: StoreDep, settings: SettingsDep) -> JobRow:
    job = store.get(job_id)
    if job is None:
        raise no_such_job(job_id, store, settings)
    return job


JobDep = Annotated[JobRow, Depends(get_job_or_404)]

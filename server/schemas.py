"""Response shapes of the REST API. The requests are the job kinds' models (`server.kinds`)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field

from server.jobs import Simulations
from server.kinds import ResultSpec
from server.status import StatusValue


class JobLinks(BaseModel):
    self: str
    result: str
    figure: str


class Job(BaseModel):
    """A job as clients see it; `error` says why it failed, `note` what happened on the way."""

    id: str
    kind: str
    status: StatusValue
    progress: float = Field(ge=0.0, le=1.0)
    created_at: str
    started_at: str | None
    finished_at: str | None
    error: str | None
    note: str | None
    attempts: int = Field(description="times a worker started this job")
    requeues: int = Field(
        description="times a crash interrupted it and it went back to the queue: the server "
        "stopped while it ran (counted against max_requeues) or its worker process died "
        "(at most once); a clean shutdown's re-queue is not counted"
    )
    sim_seconds: float = Field(description="simulated seconds the job asks for, all runs")
    simulations: Simulations | None = Field(
        None,
        description="once the job has ended (done or failed): its simulations, computed or "
        "read back from the result cache the server shares with the command line; null before "
        "(and for jobs stored by older servers)",
    )
    eta_s: float | None = Field(
        None,
        description="running jobs: estimated seconds left, from the job's own progress rate "
        "(or, before it reports progress, from recent jobs' wall time per simulated second); "
        "null otherwise",
    )
    spec: dict[str, Any]
    links: JobLinks


class JobResult(BaseModel):
    """A done job's result as JSON: its kind's result model (`server.kinds.<kind>`)."""

    job_id: str
    kind: str
    result: ResultSpec


class JobPage(BaseModel):
    items: list[Job]
    total: int
    limit: int
    offset: int


class ModelParameter(BaseModel):
    name: str  # the leaf name a job's `params` and the CLI take
    group: str  # its concern in ModelParams (body, legs, ..., numerics)
    value: float | int | bool | str | None
    origin: Literal["paper", "invented"]
    reason: str


class IntegratorInfo(BaseModel):
    name: str
    default: bool = Field(description="the integrator used when a job gives null")
    default_dt_s: float | None = Field(description="its timestep when dt_s is null")
    max_stable_dt_s: float = Field(
        description="largest dt_s accepted with it: larger steps were measured unstable "
        "(docs/NUMERICS.md)"
    )


class WorkerHealth(BaseModel):
    configured: int
    alive: int
    busy: int


class Health(BaseModel):
    status: Literal["ok", "degraded"]
    workers: WorkerHealth
    queued: int
    running: int
    queue_limit: int


class Problem(BaseModel):
    detail: str


class ValidationIssue(BaseModel):
    loc: list[str | int]
    field: str
    msg: str
    type: str
    allowed: str | None = None


class ValidationProblem(BaseModel):
    detail: list[ValidationIssue]

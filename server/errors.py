"""Turn pydantic's validation errors into messages a person can act on.

FastAPI's default 422 says "Input should be greater than 0.5" at `["body", "run", "beta"]`;
a researcher scripting sweeps needs "beta: Input should be greater than 0.5; allowed:
0.5 < beta < 1". The shape stays FastAPI's (`detail` is a list with `loc`, `msg`, `type`) so
generic clients keep working; `field` and `allowed` are added.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

from pydantic import BaseModel

from server.kinds import KIND_MODELS


def _allowed_for(model: type[BaseModel] | None, path: Sequence[str | int]) -> str | None:
    """Walk nested models along `path` and return the field's 'allowed' text, if it has one."""
    allowed: str | None = None
    for part in path:
        if model is None or not isinstance(part, str) or part not in model.model_fields:
            break
        info = model.model_fields[part]
        extra = info.json_schema_extra
        text = extra.get("allowed") if isinstance(extra, dict) else None
        allowed = text if isinstance(text, str) else None
        ann = info.annotation
        model = ann if isinstance(ann, type) and issubclass(ann, BaseModel) else None
    return allowed


def _model_at(model: type[BaseModel] | None, path: Sequence[str | int]) -> type[BaseModel] | None:
    """The model that owns the last element of `path` (for naming a nested unknown field)."""
    for part in path[:-1]:
        if model is None or not isinstance(part, str) or part not in model.model_fields:
            return None
        ann = model.model_fields[part].annotation
        model = ann if isinstance(ann, type) and issubclass(ann, BaseModel) else None
    return model


def _field_name(path: Sequence[str | int]) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else part)
    return out or "body"


ECHO_LIMIT = 200  # characters of a client's own input that a message repeats


def clip(text: str, limit: int = ECHO_LIMIT) -> str:
    """`text` if short, else its first `limit` characters and a note of how long it was: a
    message that names a 1 MB field name or tag must not send the megabyte back."""
    if len(text) <= limit:
        return text
    return f"{text[:limit]}... ({len(text)} characters, cut to {limit})"


def _clipped(err: dict[str, Any]) -> dict[str, Any]:
    """The error with every echo of the input (the location's keys, the input in the message,
    a union tag) clipped to ECHO_LIMIT characters."""
    loc = [clip(x) if isinstance(x, str) else x for x in err.get("loc", ())]
    msg = str(err.get("msg", "invalid value"))
    echoed = [err.get("input"), (err.get("ctx") or {}).get("tag")]
    for value in echoed:
        if isinstance(value, str) and len(value) > ECHO_LIMIT and value in msg:
            msg = msg.replace(value, clip(value))
    if len(msg) > 4 * ECHO_LIMIT:  # an echo not caught above: never more than a few lines
        msg = clip(msg, 4 * ECHO_LIMIT)
    return {**err, "loc": loc, "msg": msg}


def humanize(errors: Sequence[dict[str, Any]], body: Any) -> list[dict[str, Any]]:
    """Rewrite each error; `body` is the parsed request body, used to name the job kind. What
    the client sent is repeated at most ECHO_LIMIT characters at a time (`clip`)."""
    kind = body.get("kind") if isinstance(body, dict) else None
    if isinstance(kind, str):
        kind = clip(kind)
    out: list[dict[str, Any]] = []
    for err in map(_clipped, errors):
        loc = list(err.get("loc", ()))
        etype = str(err.get("type", "value_error"))
        source = loc[0] if loc else "body"
        path = loc[1:]
        model: type[BaseModel] | None = None
        if source == "body" and path and isinstance(path[0], str) and path[0] in KIND_MODELS:
            model = KIND_MODELS[path[0]]
            path = path[1:]
        elif source == "body" and isinstance(kind, str) and kind in KIND_MODELS:
            model = KIND_MODELS[kind]
        field = _field_name(path) if path else ("body" if source == "body" else str(source))
        allowed = _allowed_for(model, path)
        msg = str(err.get("msg", "invalid value"))
        owner = _model_at(model, path) if etype == "extra_forbidden" else None
        if owner is not None:
            known = ", ".join(sorted(owner.model_fields))
            where = f"kind '{kind}'" if owner is model else f"'{_field_name(path[:-1])}'"
            msg = f"unknown field '{field}' for {where}; allowed fields: {known}"
        elif etype in ("union_tag_invalid", "union_tag_not_found"):
            field = "kind"
            allowed = ", ".join(sorted(KIND_MODELS))
            if etype == "union_tag_not_found":
                msg = f"kind: missing; every job names its kind, one of: {allowed}"
            else:
                tag = clip(str(err.get("ctx", {}).get("tag", kind)))
                msg = f"kind: '{tag}' is not a job kind; choose one of: {allowed}"
        elif etype == "json_invalid":
            field = "body"
            msg = f"request body is not valid JSON: {err.get('ctx', {}).get('error', msg)}"
        elif etype == "model_attributes_type" or (etype.endswith("_type") and not path):
            msg = f"{field}: {msg}; send a JSON object"
        else:
            msg = f"{field}: {msg}"
            if allowed:
                msg += f"; allowed: {allowed}"
        out.append(
            {
                "loc": [str(x) if not isinstance(x, int) else x for x in loc],
                "field": field,
                "msg": msg,
                "type": etype,
                "allowed": allowed,
            }
        )
    return out


def limit_error(field: str, msg: str, allowed: str) -> dict[str, Any]:
    """A 422 item for limits that depend on settings (job size), in the same shape."""
    return {
        "loc": ["body", field],
        "field": field,
        "msg": f"{field}: {msg}; allowed: {allowed}",
        "type": "job_too_large",
        "allowed": allowed,
    }


_PATH = re.compile(r"(?:[A-Za-z]:)?(?:[\\/][\w.@+~-]+){2,}[\\/]?")
_URL = re.compile(r"\s*(?:For further information visit )?https?://\S+")


def sanitize(message: str, limit: int = 2000) -> str:
    """A message fit for a client: no file system paths (a path keeps only its last part), no
    traceback lines, no documentation URLs of libraries, bounded length."""
    lines = [ln for ln in message.splitlines() if ln.strip()]
    kept = [
        ln
        for ln in lines
        if not ln.lstrip().startswith(("Traceback (most recent call last)", 'File "', "^"))
    ]
    text = " ".join(ln.strip() for ln in kept)
    text = _URL.sub("", text)
    text = _PATH.sub(lambda m: m.group(0).rstrip("\\/").replace("\\", "/").rsplit("/", 1)[-1], text)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def exception_message(exc: BaseException) -> str:
    """What a client reads about an unexpected exception in a worker: its type and message,
    validation errors as `field: message`, sanitised. The traceback goes to the server log."""
    from pydantic import ValidationError

    if isinstance(exc, ValidationError):
        parts = []
        for e in exc.errors():
            loc = [p for p in e.get("loc", ()) if isinstance(p, str | int)]
            model: type[BaseModel] | None = None
            if loc and isinstance(loc[0], str) and loc[0] in KIND_MODELS:
                model = KIND_MODELS[loc[0]]
                loc = loc[1:]  # the union's tag: the job kind, not a field
            text = f"{_field_name(loc)}: {e.get('msg', 'invalid value')}"
            owner = _model_at(model, loc) if e.get("type") == "extra_forbidden" else None
            if owner is not None:  # as a 422 says it: which fields the kind does have
                text += f"; allowed fields: {', '.join(sorted(owner.model_fields))}"
            parts.append(text)
        return sanitize(f"invalid job: {'; '.join(parts)}")
    return sanitize(f"internal error ({type(exc).__name__}): {exc}")


def content_type_error(content_type: str | None) -> dict[str, Any] | None:
    """The 422 item for a body sent without a JSON Content-Type, or None if it was JSON.

    A body without any Content-Type is refused too, not guessed to be JSON (FastAPI's strict
    content type, kept on purpose): a web page can send such a body to a server on localhost
    without the browser asking first, and a server without a token would run its job."""
    main = "" if content_type is None else content_type.split(";", 1)[0].strip().lower()
    if main == "application/json" or main.endswith("+json"):
        return None
    sent = (
        "without a Content-Type header" if not main else f"with 'Content-Type: {clip(main, 100)}'"
    )
    msg = (
        f"body: the request was sent {sent}, so it was not read as JSON; set "
        "'Content-Type: application/json' (curl: -H 'Content-Type: application/json'; "
        "curl -d alone sends a form)"
    )
    return {
        "loc": ["header", "content-type"],
        "field": "body",
        "msg": msg,
        "type": "content_type",
        "allowed": "application/json",
    }


def method_not_allowed(method: str, path: str, methods: Sequence[str]) -> str:
    """A 405's detail in words: what the path takes instead."""
    if not methods:
        return f"{method} is not allowed on {clip(path)}"
    return f"{method} is not allowed on {clip(path)}; it takes {', '.join(methods)}"

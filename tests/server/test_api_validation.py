"""Every bad field gets a 422 that names the field and its allowed range, and stores nothing.

One real server with no workers serves the whole module: validation happens at the door, and a
server that runs nothing keeps the job count exact.
"""

from __future__ import annotations

import json
import re
import sqlite3
from collections.abc import Iterator
from typing import Any

import httpx
import pytest
from api_harness import SHORT, Server, free_port

BASE: dict[str, Any] = dict(SHORT)
SWEEP: dict[str, Any] = {
    "kind": "sweep",
    "beta_range": {"start": 0.6, "stop": 0.7, "steps": 3},
    "duration_s": 0.3,
}
BIFURCATION: dict[str, Any] = {**SWEEP, "kind": "bifurcation", "starts": 2, "max_borders": 0}
KINDS = "atlas, bifurcation, hysteresis, return_map, run, surface, sweep"
ATLAS: dict[str, Any] = {"kind": "atlas", "axis": "mass", "d31_step": 0.5}
SURFACE: dict[str, Any] = {"kind": "surface", "beta_range": {"start": 0.64, "stop": 0.66}}
HYSTERESIS: dict[str, Any] = {
    "kind": "hysteresis",
    "ramp": {"param": "beta", "start": 0.7, "turn": 0.62, "hold_s": 0.2, "ramp_s": 0.3},
}
# the same job in the flat shape before the ramp was the core's `Ramp` (deprecated, accepted)
FLAT_HYSTERESIS: dict[str, Any] = {
    "kind": "hysteresis",
    "parameter": "beta",
    "start": 0.7,
    "turn": 0.62,
    "hold_s": 0.2,
    "ramp_s": 0.3,
}


def ramp_(drop: str = "", **kw: Any) -> dict[str, Any]:
    """HYSTERESIS with its ramp's fields changed (`drop`: one left out)."""
    ramp = {k: v for k, v in {**HYSTERESIS["ramp"], **kw}.items() if k != drop}
    return {**HYSTERESIS, "ramp": ramp}


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    tmp = tmp_path_factory.mktemp("validation")
    srv = Server(
        db=tmp / "jobs.sqlite3",
        port=free_port(),
        env={
            "INSECT_GAIT_WORKERS": "0",
            "INSECT_GAIT_MAX_JOB_SIM_SECONDS": "100",
            "INSECT_GAIT_MAX_RUNS_PER_JOB": "20",
            "INSECT_GAIT_LOG_LEVEL": "warning",
        },
        log=tmp / "server.log",
    )
    srv.start()
    yield srv
    srv.stop()


@pytest.fixture
def client(server: Server) -> Iterator[httpx.Client]:
    with server.client() as c:
        yield c


def stored(server: Server) -> int:
    """Count rows in the database itself, not through the API under test."""
    with sqlite3.connect(server.db) as conn:
        return int(conn.execute("SELECT count(*) FROM jobs").fetchone()[0])


def with_(base: dict[str, Any], **kw: Any) -> dict[str, Any]:
    out = dict(base)
    out.update(kw)
    return out


# (body, field the message must name, text the message must contain: the allowed range)
BAD: list[tuple[dict[str, Any], str, str]] = [
    (with_(BASE, beta=0.5), "beta", "0.5 < beta < 1"),
    (with_(BASE, beta=1.0), "beta", "0.5 < beta < 1"),
    (with_(BASE, beta="0.6"), "beta", "0.5 < beta < 1"),
    (with_(BASE, beta=None), "beta", "0.5 < beta < 1"),
    (with_(BASE, body_mass_g=0), "body_mass_g", "0.5 <= body_mass_g <= 30"),
    (with_(BASE, body_mass_g=1e-9), "body_mass_g", "0.5 <= body_mass_g <= 30"),
    (with_(BASE, body_mass_g=31), "body_mass_g", "0.5 <= body_mass_g <= 30"),
    (with_(BASE, slope_deg=-90), "slope_deg", "-90 < slope_deg < 90"),
    (with_(BASE, slope_deg=95), "slope_deg", "-90 < slope_deg < 90"),
    (with_(BASE, duration_s=0), "duration_s", "0 < duration_s <= 600"),
    (with_(BASE, duration_s=601), "duration_s", "0 < duration_s <= 600"),
    (with_(BASE, dt_s=0), "dt_s", "0 < dt_s <= 0.001"),
    (with_(BASE, dt_s=0.002), "dt_s", "0 < dt_s <= 0.001"),
    (with_(BASE, dt_s=0.02), "dt_s", "0 < dt_s <= 0.001"),
    # combinations that cannot run: a step the integrator is unstable at (measured)
    (with_(BASE, dt_s=1e-3), "dt_s", "cannot be stable with integrator implicitfast"),
    (with_(BASE, integrator="euler"), "dt_s", "the default 5e-05 s) cannot be stable"),
    (with_(BASE, integrator="rk4", dt_s=2.5e-5), "dt_s", "needs dt_s <= 2e-05 s"),
    (with_(BASE, control_dt_s=1e-5), "control_dt_s", "must be >= dt_s (the default 5e-05)"),
    (with_(BASE, duration_s=1e-4), "duration_s", "shorter than one control period"),
    (with_(BASE, control_dt_s=-1e-3), "control_dt_s", "0 < control_dt_s <= 0.01"),
    (with_(BASE, dt_s=4e-4, control_dt_s=2e-4), "control_dt_s", "must be >= dt_s"),
    (with_(BASE, integrator="leapfrog"), "integrator", "euler, implicit, implicitfast, rk4"),
    (with_(BASE, phase_reset="yes"), "phase_reset", "boolean"),
    (with_(BASE, d31_init=[]), "d31_init", "1..1000 values"),
    (with_(BASE, d31_init=2.0), "d31_init", "1..1000 values"),
    (with_(BASE, d31_init=[1.0, -0.1]), "d31_init[1]", "0 <= d31_init <= 2*pi"),
    (with_(BASE, d31_init=[7.0]), "d31_init[0]", "0 <= d31_init <= 2*pi"),
    (with_(BASE, d31_init=[0.5] * 1001), "d31_init", "1..1000 values"),
    (with_(BASE, include_series=1), "include_series", "boolean"),
    (with_(BASE, ground="ice"), "ground", "one of constraint, penalty"),
    (with_(BASE, ground=1), "ground", "string"),
    (with_(BASE, colour="red"), "colour", "allowed fields: beta"),
    (with_(BASE, kind="walk"), "kind", KINDS),
    ({"beta": 0.66, "d31_init": [2.0]}, "kind", KINDS),
    ({"kind": "return_map", "lag": 0, "duration_s": 0.3}, "lag", "1 <= lag <= 50"),
    ({"kind": "return_map", "lag": 1.5, "duration_s": 0.3}, "lag", "1 <= lag <= 50"),
    ({"kind": "sweep", "duration_s": 0.3}, "beta_range", "Field required"),
    (with_(SWEEP, beta_range={"start": 0.4, "stop": 0.7}), "beta_range.start", "0.5 < start < 1"),
    (with_(SWEEP, beta_range={"start": 0.6, "stop": 1.2}), "beta_range.stop", "0.5 < stop < 1"),
    (
        with_(SWEEP, beta_range={"start": 0.6, "stop": 0.7, "steps": 1}),
        "beta_range.steps",
        "2 <= steps <= 201",
    ),
    (
        with_(SWEEP, beta_range={"start": 0.6, "stop": 0.7, "step": 0.01}),
        "beta_range.step",
        "allowed fields: start, steps, stop",
    ),
    (with_(BIFURCATION, starts=1), "starts", "2 <= starts <= 16"),
    (with_(BIFURCATION, border_tol_rad=0), "border_tol_rad", "0.005 <= border_tol_rad <= 1"),
    (with_(BIFURCATION, duration_s=1.0), "duration_s", "2 <= duration_s <= 600"),
    (with_(BIFURCATION, transient_s=0.3), "transient_s", "allowed fields"),
    (with_(ATLAS, axis="speed"), "axis", "mass, slope"),
    (with_(ATLAS, values=[0.1]), "values", "0.5 <= body_mass_g <= 30"),
    (with_(ATLAS, axis="slope", values=[95.0]), "values", "slope_deg"),
    (with_(ATLAS, betas=[0.6] * 26), "betas", "at most 25"),
    # the drift surface's pin: the core's words (sim_core.contract.pin_problem)
    (with_(SURFACE, phase_reset=False), "phase_reset", "pin_d31 needs phase resetting (eq. 4)"),
    (with_(ATLAS, phase_reset=False), "phase_reset", "pin_d31 needs phase resetting (eq. 4)"),
    # model parameters by leaf name (sim_core.contract.ModelChoice): unknown, out of range,
    # a field of the run's own, the other ground's, an unknown setting
    (with_(BASE, params={"kp_lifts": 1e-3}), "params", "unknown model parameter 'kp_lifts'"),
    (with_(BASE, params={"com_offset_x": 0.1}), "params", "less than or equal to 0.005"),
    (with_(SURFACE, params={"kp_lift": -1.0}), "params", "kp_lift: Input should be greater than 0"),
    (with_(ATLAS, params={"dt": 1e-5}), "params", "use the field dt_s"),
    (with_(BASE, params={"ground": "penalty"}), "params", "use the field ground"),
    (with_(BASE, params={"ground_stiffness": 10.0}), "params", "of the penalty ground only"),
    (with_(BASE, setting="stiff"), "setting", "known: soft_legs"),
    (with_(BASE, params={"kp_lift": "1e-3"}), "params", "kp_lift"),
    (with_(SURFACE, d31_lo=2.5, d31_hi=2.0), "d31_hi", "must be above d31_lo"),
    (with_(SURFACE, gain_per_s=0), "gain_per_s", "0 < gain_per_s <= 1000"),
    (with_(SURFACE, d31_step=0.001), "d31_step", "0.01 <= d31_step <= 1"),
    (ramp_(turn=0.7), "ramp", "ramp.turn (0.7) must differ from ramp.start"),
    (ramp_(turn=1.0), "ramp", "0.5 < beta < 1"),
    (ramp_(param="body_mass_g", start=3.0, turn=0.1), "ramp", "0.5 <= body_mass_g <= 30"),
    (ramp_(param="speed"), "ramp", "ramp.param: Input should be 'beta', 'body_mass_g'"),
    (ramp_(hold_s=60, ramp_s=250), "ramp", "at most 600 s"),
    (ramp_(hold_s=0.0), "ramp", "0 < hold_s <= 60"),
    (ramp_(drop="turn"), "ramp", "ramp.turn: Field required"),
    (ramp_(start="0.7"), "ramp", "ramp.start: Input should be a valid number"),
    (ramp_(speed=1.0), "ramp", "ramp.speed: Extra inputs are not permitted"),
    ({**FLAT_HYSTERESIS, "turn": 0.7}, "ramp", "must differ from ramp.start"),
    # limits from the settings: 20 runs and 100 simulated seconds per job
    (with_(BASE, d31_init=[1.0] * 21), "d31_init", "at most 20 simulations per job"),
    (
        with_(SWEEP, beta_range={"start": 0.6, "stop": 0.7, "steps": 30}),
        "d31_init",
        "at most 20 simulations per job",
    ),
    (with_(BASE, d31_init=[1.0] * 2, duration_s=60), "duration_s", "at most 100 simulated"),
    # issue 30: cost bounds (the core's; the CLI says the same), a finer step counts more
    (with_(BASE, dt_s=1e-12), "dt_s", "the smallest step a run may take is 1e-06 s"),
    (
        with_(BASE, duration_s=600, dt_s=1e-6, control_dt_s=5e-4),
        "duration_s",
        "6e+08 physics steps; a run may take at most 6e+07",
    ),
    ({**ramp_(hold_s=60, ramp_s=200), "dt_s": 1e-6}, "ramp", "at most 6e+07"),
    (with_(BASE, duration_s=30, dt_s=1e-5), "duration_s", "as many physics steps as 150 s"),
    # a grid of one point: refused, not run `steps` times
    (
        with_(SWEEP, beta_range={"start": 0.66, "stop": 0.66, "steps": 3}),
        "beta_range.stop",
        "equals start",
    ),
]


@pytest.mark.parametrize(
    ("body", "field", "allowed"), BAD, ids=[f"{f}-{i}" for i, (_, f, _a) in enumerate(BAD)]
)
def test_bad_field_gets_422_naming_field_and_range(
    server: Server, client: httpx.Client, body: dict[str, Any], field: str, allowed: str
) -> None:
    before = stored(server)
    r = client.post("/v1/jobs", json=body)
    assert r.status_code == 422, r.text
    issues = r.json()["detail"]
    mine = [i for i in issues if i["field"] == field]
    assert mine, f"no issue names {field!r}: {issues}"
    assert any(allowed in i["msg"] for i in mine), f"{allowed!r} not in {mine}"
    assert all(i["msg"].startswith(("unknown field", "kind:", field)) for i in mine)
    assert stored(server) == before


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        (b"{not json", "not valid JSON"),
        (b"[1, 2]", "JSON object"),
        (b'"run"', "JSON object"),
        (b'{"kind": "run", "beta": NaN}', "beta"),
    ],
)
def test_malformed_body_gets_422(
    server: Server, client: httpx.Client, content: bytes, needle: str
) -> None:
    before = stored(server)
    r = client.post("/v1/jobs", content=content, headers={"content-type": "application/json"})
    assert r.status_code == 422, r.text
    assert needle in str(r.json()["detail"])
    assert stored(server) == before


@pytest.mark.parametrize(
    ("body", "says"),
    [
        ({"beta": 0.62}, "kind: missing; every job names its kind, one of: atlas, bifurcation"),
        ({"kind": "walk"}, "kind: 'walk' is not a job kind; choose one of: atlas, bifurcation"),
    ],
)
def test_a_missing_or_unknown_kind_is_named_with_the_kinds(
    client: httpx.Client, body: dict[str, Any], says: str
) -> None:
    r = client.post("/v1/jobs", json=body)
    assert r.status_code == 422
    (err,) = r.json()["detail"]
    assert err["field"] == "kind" and err["msg"].startswith(says), err["msg"]
    assert "discriminator" not in err["msg"] and "tag" not in err["msg"]


@pytest.mark.parametrize(
    ("verb", "path", "takes"),
    [("PUT", "/v1/jobs", "GET, POST"), ("POST", "/v1/jobs/some-id", "GET, DELETE")],
)
def test_a_wrong_method_says_which_methods_the_path_takes(
    client: httpx.Client, verb: str, path: str, takes: str
) -> None:
    r = client.request(verb, path)
    assert r.status_code == 405
    assert r.json()["detail"] == f"{verb} is not allowed on {path}; it takes {takes}"
    assert r.headers["allow"] == takes


@pytest.mark.parametrize(
    ("query", "field"),
    [
        ("limit=0", "limit"),
        ("limit=201", "limit"),
        ("offset=-1", "offset"),
        ("status=ok", "status"),
    ],
)
def test_bad_query_gets_422(client: httpx.Client, query: str, field: str) -> None:
    r = client.get(f"/v1/jobs?{query}")
    assert r.status_code == 422
    assert r.json()["detail"][0]["field"] == field


def test_bad_result_format_gets_422(client: httpx.Client) -> None:
    r = client.get("/v1/jobs/nope/result?format=xml")
    assert r.status_code == 422
    assert "format" in r.json()["detail"][0]["msg"]


@pytest.mark.parametrize("verb", ["get", "delete"])
@pytest.mark.parametrize("suffix", ["", "/result", "/figure.png"])
def test_unknown_job_is_404(client: httpx.Client, verb: str, suffix: str) -> None:
    if verb == "delete" and suffix:
        return
    r = client.request(verb.upper(), f"/v1/jobs/no-such-job{suffix}")
    assert r.status_code == 404
    assert "no-such-job" in r.json()["detail"]


def test_good_job_is_stored_queued_with_defaults(server: Server, client: httpx.Client) -> None:
    before = stored(server)
    r = client.post("/v1/jobs", json={"kind": "return_map", "beta": 0.7, "duration_s": 0.3})
    assert r.status_code == 202, r.text
    job = r.json()
    assert r.headers["location"] == f"/v1/jobs/{job['id']}"
    assert job["status"] == "queued" and job["progress"] == 0.0
    assert job["spec"]["lag"] == 4 and len(job["spec"]["d31_init"]) == 12
    assert job["sim_seconds"] == pytest.approx(12 * 0.3)
    assert stored(server) == before + 1
    page = client.get("/v1/jobs", params={"status": "queued", "limit": 1}).json()
    assert page["items"][0]["id"] == job["id"] and page["total"] >= 1
    # no workers here: a result is refused with the reason
    r = client.get(f"/v1/jobs/{job['id']}/result")
    assert r.status_code == 409 and "queued" in r.json()["detail"]


def test_openapi_docs_are_served(client: httpx.Client) -> None:
    assert client.get("/docs").status_code == 200
    paths = client.get("/openapi.json").json()["paths"]
    assert {"/v1/jobs", "/v1/jobs/{job_id}", "/v1/jobs/{job_id}/result"} <= set(paths)


def test_every_kinds_result_schema_is_in_openapi(client: httpx.Client) -> None:
    from server.kinds import KINDS

    spec = client.get("/openapi.json").json()
    ok = spec["paths"]["/v1/jobs/{job_id}/result"]["get"]["responses"]["200"]["content"]
    assert ok["application/json"]["schema"] == {"$ref": "#/components/schemas/JobResult"}
    assert "text/csv" in ok
    schemas = spec["components"]["schemas"]
    result = schemas["JobResult"]["properties"]["result"]
    mapping = result["discriminator"]["mapping"]
    assert set(mapping) == set(KINDS)  # one result model per kind, told apart by `kind`
    for name, kind in KINDS.items():
        model = schemas[kind.result.__name__]
        assert mapping[name] == f"#/components/schemas/{kind.result.__name__}"
        assert "records" in model["required"] and model["properties"]["kind"]["const"] == name


@pytest.mark.parametrize("page", ["/docs", "/redoc"])
def test_docs_work_offline(client: httpx.Client, page: str) -> None:
    """No external URL in the page: every script, style and icon it loads is served here."""
    r = client.get(page)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    html = r.text
    assert "http://" not in html and "https://" not in html and "//cdn" not in html
    assets = re.findall(r'(?:src|href)="([^"]+)"', html)
    assert any(a.endswith(".js") for a in assets)
    for asset in assets:
        got = client.get(asset)
        assert got.status_code == 200 and len(got.content) > 1000, asset


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        (b'{"kind": "run", "beta": \xff}', "not valid UTF-8 (byte 0xff"),
        (b'{"kind": "run", "beta": ' + b"1" * 5001 + b"}", "more than 4300 digits"),
        (b"[" * 100_000 + b"]" * 100_000, "nested too deeply"),
    ],
)
def test_unparsable_body_gets_documented_400(
    server: Server, client: httpx.Client, content: bytes, needle: str
) -> None:
    before = stored(server)
    r = client.post("/v1/jobs", content=content, headers={"content-type": "application/json"})
    assert r.status_code == 400, r.text
    assert needle in r.json()["detail"]
    assert stored(server) == before
    documented = client.get("/openapi.json").json()["paths"]["/v1/jobs"]["post"]["responses"]
    assert "400" in documented


@pytest.mark.parametrize("ctype", ["text/plain", "application/x-www-form-urlencoded"])
def test_json_without_json_content_type_names_the_header(client: httpx.Client, ctype: str) -> None:
    r = client.post("/v1/jobs", content=json.dumps(SHORT).encode(), headers={"content-type": ctype})
    assert r.status_code == 422, r.text
    (issue,) = r.json()["detail"]
    assert f"Content-Type: {ctype}" in issue["msg"]
    assert "Content-Type: application/json" in issue["msg"]


def test_json_without_any_content_type_says_to_set_it(server: Server, client: httpx.Client) -> None:
    """Issue 30: a valid JSON body without the header was told to 'send a JSON object'."""
    before = stored(server)
    request = client.build_request("POST", "/v1/jobs", content=json.dumps(SHORT).encode())
    assert "content-type" not in request.headers  # httpx sets none for raw bytes
    r = client.send(request)
    assert r.status_code == 422, r.text
    (issue,) = r.json()["detail"]
    assert "without a Content-Type header" in issue["msg"]
    assert "set 'Content-Type: application/json'" in issue["msg"]
    assert "send a JSON object" not in issue["msg"]
    assert stored(server) == before


@pytest.mark.parametrize(
    "body",
    [
        {"kind": "x" * 1_000_000},
        {**SHORT, "y" * 1_000_000: 1},
        {**SWEEP, "beta_range": {"start": 0.6, "stop": 0.7, "z" * 1_000_000: 1}},
    ],
    ids=["kind", "unknown-field", "nested-unknown-field"],
)
def test_a_huge_input_is_not_echoed_back(client: httpx.Client, body: dict[str, Any]) -> None:
    """Issue 30: a 422 repeated a 1 MB input in full; now at most 200 characters, with a note."""
    r = client.post("/v1/jobs", json=body)
    assert r.status_code == 422
    assert len(r.content) < 3000, len(r.content)
    assert "(1000000 characters, cut to 200)" in r.text


def test_integrators_listed_as_the_core_has_them(client: httpx.Client) -> None:
    from sim_core.contract import INTEGRATORS, ModelParams

    listed = client.get("/v1/integrators").json()
    assert tuple(i["name"] for i in listed) == tuple(INTEGRATORS)
    assert [i["name"] for i in listed if i["default"]] == [ModelParams().numerics.integrator]
    schema = client.get("/openapi.json").json()["components"]["schemas"]["RunJob"]
    text = json.dumps(schema["properties"]["integrator"])
    assert all(name in text for name in INTEGRATORS)  # discrete included


def test_bounds_say_why_in_the_schema(client: httpx.Client) -> None:
    props = client.get("/openapi.json").json()["components"]["schemas"]["RunJob"]["properties"]
    assert "cannot be stable" in json.dumps(props["dt_s"])
    assert "euler 1e-05 s" in json.dumps(props["dt_s"])
    assert "six legs" in props["body_mass_g"]["description"]


def test_model_parameters(client: httpx.Client) -> None:
    from sim_core.contract import parameter_table

    r = client.get("/v1/model")
    assert r.status_code == 200
    rows = r.json()
    assert [row["name"] for row in rows] == [row[0] for row in parameter_table()]
    assert {row["origin"] for row in rows} <= {"paper", "invented"}


def test_a_job_too_large_for_memory_is_refused_by_the_core_rule() -> None:
    """Memory per job (issue 30): runs held at once x their records; the series as JSON-able
    lists cost ~17x the bare arrays (measured), so include_series reaches the bound first."""
    from server.kinds.run import RunJob
    from sim_core.contract import MAX_JOB_BYTES, cost_problem, run_cost

    small = RunJob(d31_init=[2.0] * 3, duration_s=600)
    assert small.cost_problem() is None
    big = RunJob(d31_init=[2.0] * 3, duration_s=600, include_series=True)
    problem = big.cost_problem()
    assert problem is not None and "GiB" in problem and "include_series" in problem
    assert problem == cost_problem(600, None, None, None, runs=3, series=True)
    one = run_cost(600, 5e-5, 5e-4, series=True)
    assert one.records == 300_002 and 3 * one.bytes > MAX_JOB_BYTES > one.bytes

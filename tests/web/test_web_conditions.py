"""The panels draw data of the walk's own conditions (web/conditions.py, web/surfaces.py,
web/surface_jobs.py): which surface and finder cells match a walk, what the panel says when
none does, the surface job the viewer submits and follows (against a small fake API), and the
loop's panels after switching to the paper's ground and to 6 g (no browser)."""

from __future__ import annotations

import html
import json
import re
import shutil
import threading
import time
from collections.abc import Callable, Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any, ClassVar, TypeVar

import pytest

from sim_core.contract import (
    DriftSurface,
    EventConditions,
    FinderOutput,
    ModelChoice,
    SurfaceAtlas,
)
from web.bifurcation import WatchedFile, load_validated
from web.conditions import (
    Conditions,
    atlas_conditions,
    atlas_holds,
    atlas_label,
    events_of,
    finder_conditions,
    finder_for,
    ground_words,
    of_surface,
)
from web.controls import GROUND_LABEL
from web.panel_labels import COMPUTE_SURFACE
from web.record import D31Event
from web.surface_jobs import SurfaceJobs, surface_job_body, surface_of
from web.surface_svg import surface_svg
from web.surfaces import SurfaceFiles, pick_finder, pick_surface

FIGURES = Path(__file__).resolve().parents[2] / "docs" / "figures"
TODAY = Conditions("constraint", 3.0, 0.0)
PAPER = Conditions("penalty", 3.0, 0.0)
T = TypeVar("T")
PAPER_6G = Conditions("penalty", 6.0, 0.0)


def title(svg: str) -> str:
    """A panel's title as read: its lines (it wraps) joined by a space, unescaped."""
    head = re.search(r'<text class="title"[^>]*>(.*?)</text>', svg)
    assert head is not None, svg[:200]
    return html.unescape(" ".join(re.findall(r"<tspan[^>]*>(.*?)</tspan>", head.group(1))))


def _surface(name: str) -> DriftSurface:
    s, note = load_validated(FIGURES / name, DriftSurface, "drift surface")
    assert s is not None, note
    return s


def test_conditions_match_at_the_same_slider_positions_only() -> None:
    assert Conditions("penalty", 5.96, 0.2).matches(Conditions("penalty", 6.04, -0.2))
    assert not PAPER_6G.matches(Conditions("penalty", 6.1, 0.0))  # the next mass step
    assert not PAPER_6G.matches(Conditions("penalty", 6.0, 0.5))  # the next slope step
    assert not PAPER.matches(TODAY)  # another ground
    assert Conditions("constraint", 3.0, -0.0).matches(TODAY)
    paper, today = (ground_words(g) for g in ("penalty", "constraint"))
    assert GROUND_LABEL["penalty"] in paper and "ground" in paper  # the button's name
    assert PAPER_6G.label() == f"{paper}, 6.0 g, slope 0°"
    assert Conditions("constraint", 2.96, -12.4).label() == f"{today}, 3.0 g, slope -12.5°"
    assert Conditions("penalty", 5.96, 0.2).snapped() == PAPER_6G


def test_the_results_surfaces_name_their_conditions() -> None:
    assert of_surface(_surface("surface.json")).matches(TODAY)
    assert of_surface(_surface("surface_penalty.json")).matches(PAPER)


def test_the_finder_cells_of_the_walks_conditions_only() -> None:
    out, note = load_validated(FIGURES / "bifurcation.json", FinderOutput, "finder results")
    assert out is not None, note
    # written by `reproduce` on the default model: the constraint ground, 3 g, level
    assert [c.label() for c in finder_conditions(out)] == [TODAY.label()]
    mine = finder_for(out, TODAY)
    assert mine is not None and len(mine.cells) == len(out.cells)
    assert (
        finder_for(out, PAPER) is None and finder_for(out, Conditions("constraint", 6, 0)) is None
    )
    # a file of mixed conditions is cut to the walk's cells
    half = len(out.cells) // 2
    heavy = [c.model_copy(update={"body_mass_g": 6.0}) for c in out.cells[:half]]
    mixed = out.model_copy(update={"cells": heavy + out.cells[half:]})
    six = finder_for(mixed, Conditions("constraint", 6.0, 0.0))
    assert six is not None and len(six.cells) == half
    # its config is the finder's protocol (`FinderConfig`), which names no ground: a file
    # that names one there is refused, not read as walked on the default ground
    named = json.loads(out.model_dump_json())
    named["config"]["ground"] = "penalty"
    with pytest.raises(ValueError, match="ground"):
        FinderOutput.model_validate(named)


def test_the_bifurcation_panel_says_which_conditions_the_file_holds(tmp_path: Path) -> None:
    shutil.copy(FIGURES / "bifurcation.json", tmp_path)
    watched = WatchedFile(tmp_path / "bifurcation.json", FinderOutput, "finder results")
    assert pick_finder(watched, TODAY)[0] is not None
    out, note = pick_finder(watched, PAPER_6G)
    assert out is None
    assert f"no finder results for {PAPER_6G.label()}" in note
    assert f"holds {TODAY.label()}" in note


def _folder(tmp_path: Path) -> Path:
    for name in ("surface.json", "surface_penalty.json", "surface_atlas_mass_penalty.json"):
        shutil.copy(FIGURES / name, tmp_path)
    return tmp_path


def test_the_surface_of_the_walks_conditions_is_picked_else_the_panel_says_none(
    tmp_path: Path,
) -> None:
    files = SurfaceFiles(_folder(tmp_path), tmp_path / "surface.json")
    assert [p.name for p in files.paths()] == ["surface.json", "surface_penalty.json"]
    jobs = SurfaceJobs()
    today = pick_surface(files, jobs, TODAY)
    assert today.surface is not None and today.surface.ground == "constraint" and not today.offer
    paper = pick_surface(files, jobs, PAPER)
    assert paper.surface is not None and paper.surface.ground == "penalty"
    none = pick_surface(files, jobs, PAPER_6G)
    assert none.surface is None and none.offer
    assert none.note.startswith(f"no drift surface for {PAPER_6G.label()}")
    assert COMPUTE_SURFACE in none.note
    assert PAPER.label() in none.note  # what the folder has instead
    # a file that does not validate is named; an absent folder is just empty
    (tmp_path / "surface_broken.json").write_text("{}")
    assert "surface_broken.json is not a DriftSurface" in pick_surface(files, jobs, PAPER_6G).note
    assert SurfaceFiles(tmp_path / "nowhere").paths() == []
    # the panel names the conditions in its title and draws no live point without a surface
    svg = surface_svg(None, none.note, (0.66, None), (0.55, 0.8), conditions=PAPER_6G.label())
    assert title(svg).endswith(f"— {PAPER_6G.label()}") and 'class="live"' not in svg


def test_only_the_events_taken_under_the_conditions_are_drawn() -> None:
    def event(mass: float, ground: str = "penalty") -> D31Event:
        return D31Event(1.0, 2.0, EventConditions(0.66, mass, 0.0, ground))

    events = [event(3.0), event(6.0), event(6.02), event(6.0, "constraint")]
    assert events_of(events, PAPER_6G) == events[1:3]


def test_the_atlas_live_point_needs_the_value_it_holds_fixed() -> None:
    held = atlas_conditions("penalty")  # 3 g, level: what `insect-gait atlas` holds
    assert atlas_holds("mass", held, PAPER_6G)  # over mass: any mass, level ground
    assert not atlas_holds("mass", held, Conditions("penalty", 3.0, 5.0))
    assert not atlas_holds("slope", held, PAPER_6G)  # over slope: at 3 g only
    assert not atlas_holds("mass", held, Conditions("constraint", 3.0, 0.0))


def test_the_surface_job_body_is_the_services_surface_kind() -> None:
    from server.kinds.surface import SurfaceJob

    job = SurfaceJob.model_validate(surface_job_body(Conditions("penalty", 5.98, 0.2)))
    assert (job.ground, job.body_mass_g, job.slope_deg) == ("penalty", 6.0, 0.0)
    assert job.beta_range.values()[0] == 0.6 and job.beta_range.values()[-1] == 0.72
    # within what a service with the default settings accepts (the route's limits)
    from server.settings import Settings

    limits = Settings()
    assert job.run_count() <= limits.max_runs_per_job
    assert job.size_sim_seconds() <= limits.max_job_sim_seconds and job.cost_problem() is None


class _FakeApi(BaseHTTPRequestHandler):
    """POST /v1/jobs, then GET the job (queued, running 50% until the test releases it, done)
    and its result. The test holds the job at 50% until it has seen that state: a job that
    finished after a fixed number of polls raced the test's reading of it (under load the
    reading thread could sleep through the whole running window)."""

    surface: ClassVar[dict[str, Any]] = {}
    polls = 0
    posted: ClassVar[list[dict[str, Any]]] = []
    release: ClassVar[threading.Event] = threading.Event()

    def _send(self, body: dict[str, Any]) -> None:
        data = json.dumps(body).encode()
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        self.wfile.write(data)

    def do_POST(self) -> None:
        n = int(self.headers["Content-Length"])
        type(self).posted.append(json.loads(self.rfile.read(n)))
        self._send({"id": "j1", "kind": "surface", "status": "queued", "progress": 0.0})

    def do_GET(self) -> None:
        if self.path.endswith("/result"):
            self._send({"job_id": "j1", "kind": "surface", "result": {"surface": self.surface}})
            return
        type(self).polls += 1
        status = "done" if self.release.is_set() else "running"
        self._send({"id": "j1", "kind": "surface", "status": status, "progress": 0.5})

    def log_message(self, *args: Any) -> None:
        pass


@pytest.fixture()
def fake_api() -> Iterator[str]:
    server = ThreadingHTTPServer(("127.0.0.1", 0), _FakeApi)
    _FakeApi.polls, _FakeApi.posted, _FakeApi.release = 0, [], threading.Event()
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()


def _poll(read: Callable[[], T], ok: Callable[[T], bool], what: str, timeout_s: float = 60.0) -> T:
    """Read until `ok` holds (a thread's progress under load: generous, no fixed timing) and
    return the value that passed; on timeout the message names the last value read."""
    deadline = time.monotonic() + timeout_s
    value = read()
    while not ok(value):
        if time.monotonic() > deadline:
            raise AssertionError(f"{what} never held within {timeout_s:g} s; last read {value!r}")
        time.sleep(0.02)
        value = read()
    return value


def test_a_surface_job_is_followed_then_drawn(tmp_path: Path, fake_api: str) -> None:
    # the service's answer: the paper's-ground surface, as computed at 6 g
    six = _surface("surface_penalty.json").model_copy(update={"body_mass_g": 6.0})
    _FakeApi.surface = json.loads(six.model_dump_json())
    files = SurfaceFiles(_folder(tmp_path))
    jobs = SurfaceJobs(poll_s=0.3)
    assert jobs.submit(fake_api, PAPER_6G)
    assert not jobs.submit(fake_api, PAPER_6G)  # one job per condition at a time
    seen = []

    def pick() -> Any:
        seen.append(pick_surface(files, jobs, PAPER_6G))
        return seen[-1]

    computing = f"computing the drift surface for {PAPER_6G.label()}"
    _poll(pick, lambda p: p.surface is None and computing in p.note and "50%" in p.note,
          f"a note {computing!r} at 50%")  # fmt: skip
    _FakeApi.release.set()  # the job finishes now
    _poll(pick, lambda p: p.surface is not None, "the job's surface drawn")
    assert not any(p.offer for p in seen)  # no second offer while it runs
    assert _FakeApi.posted == [surface_job_body(PAPER_6G)]
    assert seen[-1].surface == six
    assert pick_surface(files, jobs, PAPER).surface != six  # 3 g keeps the folder's


def test_the_services_surface_result_is_read_and_one_of_other_conditions_refused() -> None:
    from server.kinds.surface import SurfaceJobResult

    penalty = _surface("surface_penalty.json")
    # what GET /v1/jobs/{id}/result answers for a surface job (server/routes/jobs.py)
    stored = SurfaceJobResult(surface=penalty, records=[]).model_dump(mode="json")
    answer = json.loads(json.dumps({"job_id": "j1", "kind": "surface", "result": stored}))
    assert surface_of(answer, PAPER) == (penalty, "")
    got = {"result": {"surface": json.loads(_surface("surface_penalty.json").model_dump_json())}}
    surface, note = surface_of(got, PAPER_6G)
    assert surface is None
    assert note == f"the job computed {PAPER.label()}, not {PAPER_6G.label()}"
    assert surface_of({"result": {"surface": {}}}, PAPER)[1].startswith(
        "the job's result is not a DriftSurface"
    )


def test_the_surface_button_asks_for_the_walks_model_parameters(fake_api: str) -> None:
    """Issue 53: the viewer's own loop with a leaf off its default (`insect-gait viewer
    --param`): the folder's surface of the defaults is not this walk's map, so the panel offers
    the job; the button's job carries the walk's ModelChoice, which the service's kind takes;
    the surface it returns for those parameters is then drawn, one of others refused."""
    from server.kinds.surface import SurfaceJob
    from web.app import ViewerApp
    from web.requests import SubmitSurface

    model = ModelChoice(ground="penalty", params={"kp_lift": 0.001})
    app = ViewerApp("127.0.0.1", 0, model=model, api_url=fake_api)
    try:
        app.charts.draw()
        assert app.panels.surface_compute.visible  # surface_penalty.json: the defaults'
        assert "kp_lift 0.001" in html.unescape(app.panels.surface.content)
        app.apply(SubmitSurface())
        posted = _poll(lambda: list(_FakeApi.posted), bool, "the surface job's POST")
        assert posted[0]["params"] == {"kp_lift": 0.001} and posted[0]["ground"] == "penalty"
        job = SurfaceJob.model_validate(posted[0])
        assert job.model_params() == model.model_params()
        assert (job.body_mass_g, job.slope_deg) == (PAPER.body_mass_g, PAPER.slope_deg)
        # the service computes the surface of those parameters (it records their leaves)
        mine = _surface("surface_penalty.json").model_copy(update={"params": model.changed()})
        _FakeApi.surface = json.loads(mine.model_dump_json())
        _FakeApi.release.set()
        _poll(lambda: app.surface_jobs.state(PAPER)[0], bool, "the job's surface kept")
        app.charts.draw()
        assert not app.panels.surface_compute.visible and 'data-n-cells="0"' not in (
            app.panels.surface.content
        )
        # a surface of the defaults returned for this walk's job is refused, naming why
        plain = {
            "result": {"surface": json.loads(_surface("surface_penalty.json").model_dump_json())}
        }
        assert surface_of(plain, PAPER, model) == (
            None, "the job computed other model parameters than kp_lift 0.001"
        )  # fmt: skip
    finally:
        app.stop()


def test_the_loops_panels_follow_the_ground_and_the_mass() -> None:
    """The viewer's own loop (not started: one thread), its panels drawn after the walk moves
    to the paper's ground and then to 6 g."""
    from web.app import ViewerApp
    from web.requests import SetGround, SetParam

    app = ViewerApp("127.0.0.1", 0)
    try:
        app.apply(SetGround("penalty"))
        app.step(0.4, time.perf_counter() + 600)
        app.charts.draw()
        surface, bif = app.panels.surface.content, app.panels.bifurcation.content
        assert title(surface).endswith(f"— {PAPER.label()}")
        assert 'data-n-cells="0"' not in surface  # surface_penalty.json is drawn
        assert not app.panels.surface_compute.visible
        assert title(bif).endswith(f"— {PAPER.label()}")
        assert f"no finder results for {PAPER.label()}" in bif and 'class="stable"' not in bif
        assert title(app.panels.atlas.content).endswith(f"— {ground_words('penalty')}, slope 0°")

        app.apply(SetParam("body_mass_g", 6.0))
        app.step(0.4, time.perf_counter() + 600)
        app.charts.draw()
        surface = app.panels.surface.content
        assert title(surface).endswith(f"— {PAPER_6G.label()}")
        assert (
            f"no drift surface for {PAPER_6G.label()}" in surface and 'class="live"' not in surface
        )
        assert app.panels.surface_compute.visible
        assert title(app.panels.bifurcation.content).endswith(f"— {PAPER_6G.label()}")
    finally:
        app.stop()


def test_the_titled_panels_stay_legible_and_the_atlas_holds_its_live_point() -> None:
    from tests.web.test_svg_legible import clashes
    from web.atlas_svg import atlas_svg
    from web.bifurcation_svg import bifurcation_svg

    longest = Conditions("constraint", 10.0, -27.5)  # the widest label the sliders make
    atlas, note = load_validated(FIGURES / "surface_atlas_mass_penalty.json", SurfaceAtlas, "")
    assert atlas is not None, note
    betas = (0.55, 0.80)
    svgs = {
        "surface": surface_svg(
            _surface("surface.json"), "", (0.66, 2.3), betas, conditions=longest.label()
        ),
        "bifurcation": bifurcation_svg(
            None, "", [], (0.66, 2.0), betas, conditions=longest.label()
        ),
        "atlas": atlas_svg(
            atlas,
            "",
            "mass",
            "body mass (g)",
            None,
            betas,
            conditions=atlas_label("slope", longest),
        ),
    }
    for name, svg in svgs.items():
        assert clashes(svg) == [], (name, clashes(svg))
    assert title(svgs["surface"]).endswith(f"— {longest.label()}")
    assert 'class="live"' not in svgs["atlas"]  # the walk is not at the value it holds
    drawn = atlas_svg(atlas, "", "mass", "body mass (g)", (0.66, 3.0), betas)
    assert 'class="live"' in drawn

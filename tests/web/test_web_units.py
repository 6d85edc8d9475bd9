"""The viewer's pure parts: slider mapping, ramp, request queue, buffers, pacing, readouts."""

import math
import re
import threading

import numpy as np
import pytest

from sim_core import RunSpec
from sim_core.contract import EventConditions as Conditions
from web import controls
from web.d31_svg import CHAR_W, d31_svg
from web.footfall_svg import footfall_svg
from web.readouts import Readouts, format_readouts
from web.record import D31Conditions, D31Event, d31_since, stance_intervals
from web.requests import Request, RequestQueue, Reset, SetParam, StartRamp, StopRamp, coalesce
from web.state import RateMeter, SimClock
from web.svg import n_dots


def test_sliders_map_to_values_the_core_accepts() -> None:
    assert controls.beta_value(0.62) == 0.62
    assert controls.beta_value(2.0) == controls.BETA.hi
    assert controls.beta_value(float("nan")) == controls.BETA.initial
    assert controls.body_mass_g_value(-1) == controls.BODY_MASS_G.lo
    assert controls.slope_deg_value(45) == controls.SLOPE_DEG.hi
    assert controls.d31_init_value(100) <= 2 * math.pi
    for s in (controls.BETA, controls.BODY_MASS_G, controls.SLOPE_DEG):
        # every slider end is a valid RunSpec value
        RunSpec(
            beta=controls.beta_value(s.lo if s is controls.BETA else 0.66),
            body_mass_g=controls.body_mass_g_value(s.lo if s is controls.BODY_MASS_G else 3),
            slope_deg=controls.slope_deg_value(s.hi if s is controls.SLOPE_DEG else 0),
        )
    assert controls.speed_value("max") is None and controls.speed_value("0.1x") == 0.1


def test_the_ramp_is_the_cores_schedule_with_hold_phases() -> None:
    from sim_core.contract import Ramp

    ramp = controls.make_ramp("body_mass_g", 3.0, 60.0, 1.0, 2.0)  # turn clamped to 10 g
    assert isinstance(ramp, Ramp) and ramp.turn == controls.BODY_MASS_G.hi
    phases = [ramp.phase(t) for t in (0.5, 1.5, 3.5, 5.5, 6.0)]
    assert phases == ["hold", "up", "down", "hold", "done"]
    assert ramp.value(0.5) == 3.0 and ramp.value(2.0) == pytest.approx(6.5)
    assert ramp.value(3.0) == pytest.approx(10.0) and ramp.value(5.5) == 3.0
    down = controls.make_ramp("beta", 0.70, 0.62, 0.0, 1.0)
    assert [down.phase(t) for t in (0.5, 1.5)] == ["down", "up"]
    with pytest.raises(ValueError):
        controls.make_ramp("gravity", 1.0, 2.0, 1.0, 1.0)


def test_coalesce_keeps_only_the_latest_setting_but_respects_order() -> None:
    reqs: list[Request] = [
        SetParam("beta", 0.6),
        SetParam("beta", 0.61),
        SetParam("slope_deg", 2.0),
        SetParam("beta", 0.62),
    ]
    assert coalesce(reqs) == [SetParam("beta", 0.62), SetParam("slope_deg", 2.0)]
    ordered: list[Request] = [
        SetParam("beta", 0.6),
        StartRamp(controls.make_ramp("beta", 0.7, 0.62, 1.0, 1.0)),
        SetParam("beta", 0.7),
        StopRamp(),
        Reset(2.0),
        SetParam("beta", 0.65),
    ]
    assert coalesce(ordered) == ordered


def test_request_queue_is_safe_across_threads() -> None:
    q = RequestQueue()

    def push(k: int) -> None:
        for i in range(200):
            q.put(Reset(float(k * 1000 + i)))

    threads = [threading.Thread(target=push, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    drained = q.drain()
    assert len(drained) == 800 and q.drain() == []


def test_every_request_type_has_its_handler_and_a_second_one_is_refused() -> None:
    """The loop applies a request by its type's handler (web/handlers.py): every type a
    callback may queue has one, and registering another for the same type fails."""
    from typing import get_args

    from web.handlers import HANDLERS, handles

    assert set(HANDLERS) == set(get_args(Request)) and len(HANDLERS) == 20
    with pytest.raises(RuntimeError, match="SetParam has a handler already"):
        handles(SetParam)(lambda viewer, req: None)


def test_stance_samples_make_one_bar_per_interval() -> None:
    t = np.arange(21) * 0.1
    s = np.ones((21, 6), dtype=bool)
    s[:, 0] = [k % 4 < 2 for k in range(21)]  # R1: on 2 samples, off 2, ...
    s[20, 2] = False  # R2 lifts at the last sample
    s[:20, 4] = False  # R3 lands at the last sample: nothing to draw yet
    bars = stance_intervals(t, s)
    assert len(bars) == 6
    # sample i stands for [t_i, t_i+1): on at 0.0 and 0.1, off at 0.2 -> (0.0, 0.2)
    assert bars[0][:2] == [pytest.approx((0.0, 0.2)), pytest.approx((0.4, 0.6))]
    # ... and lands again at the last sample: an interval of no length yet is not a bar
    assert len(bars[0]) == 5 and bars[0][-1] == pytest.approx((1.6, 1.8))
    assert bars[1] == [pytest.approx((0.0, 2.0))]  # still on: ends at the last sample
    assert bars[2] == [pytest.approx((0.0, 2.0))]  # lifted at the last sample
    assert bars[4] == []
    assert stance_intervals(np.zeros(0), np.zeros((0, 6), bool)) == [[] for _ in range(6)]


class Run:
    """A live run's record as the core keeps it: events, and what was in force at each."""

    def __init__(self) -> None:
        self.d31_events: list[tuple[float, float]] = []
        self.d31_conditions: list[Conditions] = []

    def add(self, events: list[tuple[float, float]], at: Conditions) -> None:
        self.d31_events.extend(events)
        self.d31_conditions.extend(at for _ in events)


def at(
    beta: float, mass: float = 3.0, slope: float = 0.0, ramp: str = "", param: str = ""
) -> Conditions:
    return Conditions(beta, mass, slope, ramp=ramp, ramp_param=param)


def test_the_viewer_reads_the_cores_events_with_their_conditions() -> None:
    run = Run()
    run.add([(0.1, 2.0), (0.2, 2.1)], at(0.66))
    log = D31Conditions()
    log.note(run)
    run.add([(0.3, 2.2)], at(0.65))  # the core extends its lists in place
    ev = log.events(run)
    assert [(e.time_s, e.d31, e.at.beta) for e in ev] == [
        (0.1, 2.0, 0.66), (0.2, 2.1, 0.66), (0.3, 2.2, 0.65)
    ]  # fmt: skip
    assert [e.time_s for e in log.events(run, -2)] == [0.2, 0.3]
    core = run.d31_events
    assert d31_since(core, 0.2) == [(0.2, 2.1), (0.3, 2.2)] and d31_since(core, 0.35) == []
    run.d31_events.append((0.4, 2.3))  # an event whose conditions are not there: not shown
    assert len(log.events(run)) == 3
    log.note(run)
    assert len(log) == 3
    again = Run()
    again.add([(0.05, 1.0)], at(0.7))  # the core started over
    log.note(again)
    assert len(log) == 1 and [(e.time_s, e.at.beta) for e in log.events(again)] == [(0.05, 0.7)]


def test_sim_clock_caps_the_debt_when_the_machine_is_slow() -> None:
    clock = SimClock(max_lag_s=0.2)
    assert clock.tick(0.1, 1.0) == pytest.approx(0.1)
    clock.paid(0.1)
    assert clock.tick(10.0, 1.0) == pytest.approx(0.2)  # not 10 s of catching up
    clock.paid(0.2)
    assert clock.lag_s == pytest.approx(9.8)  # but the status says how far behind it is
    clock.reset()
    assert clock.lag_s == 0.0
    meter = RateMeter(window_s=1.0)
    meter.add(0.0, 0.0)
    meter.add(1.0, 0.5)
    assert meter.rate == pytest.approx(0.5)


def test_readouts_say_when_the_viewer_falls_behind() -> None:
    r = Readouts(0.66, 1.0, 2.5, 0.66, "tripod", 3.0, 0.5, 1.2, 1.0, 30.0, "")
    assert "behind" in format_readouts(r)["status"]
    ok = Readouts(0.66, 1.0, 2.5, 0.66, "tripod", 3.0, 1.0, 1.2, 1.0, 30.0, "")
    assert "keeping up" in format_readouts(ok)["status"]
    err = Readouts(0.66, 1.0, None, None, "other", 3.0, None, None, 1.0, None, "", "diverged")
    assert "stopped" in format_readouts(err)["status"]


def test_svg_panels_carry_their_data() -> None:
    bars = [[(0.5, 0.8)], [], [(0.1, 0.2), (0.6, 0.9)], [], [], []]
    svg = footfall_svg(bars, 1.0, 1.0)
    assert svg.startswith("<svg") and svg.count("<rect") >= 3
    ev = [(t, 2.0 + 0.1 * t) for t in np.linspace(0.1, 0.9, 5)]
    d = d31_svg(ev, 1.0, 1.0, "metachronal")
    assert "metachronal" in d and "<svg" in d


def test_d31_line_breaks_where_the_angle_wraps() -> None:
    ev = [(0.1, 6.2), (0.2, 0.05), (0.3, 0.1), (0.4, math.nan)]
    d = d31_svg(ev, 1.0, 1.0, "other")
    assert d.count("<polyline") == 1  # 6.2 -> 0.05 is a wrap, not a line through pi
    assert n_dots(d) == 3 and "nan" not in d  # a non-finite value is not drawn


def test_a_typed_keystroke_outside_the_range_is_not_a_value_yet() -> None:
    # typing "0.62" sends 0, 0, 0.6, 0.62: only the in-range ones are values
    assert controls.BETA.typed(0.0) is None
    assert controls.BETA.typed(0.6) == 0.6 and controls.BETA.typed(0.62) == 0.62
    assert controls.BETA.typed(float("nan")) is None  # a lone "-" or "."
    assert controls.SLOPE_DEG.typed(-7.5) == -7.5 and controls.SLOPE_DEG.typed(-75) is None
    assert controls.BODY_MASS_G.typed(10.0) == 10.0 and controls.BODY_MASS_G.typed(45) is None


def test_the_follow_camera_can_turn_the_world_so_the_body_faces_x() -> None:
    import viser.transforms as vtf

    from web.scene import world_pose

    def quat_rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
        return vtf.SO3(np.asarray(q, dtype=float)).apply(np.asarray(v, dtype=float))

    body = np.array([0.03, 0.04, 0.01])
    q, p = world_pose(0.0, controls.CAMERA_HEADING, body, math.pi / 2)
    shown = quat_rotate(q, body * np.array([1, 1, 0])) + p
    assert shown == pytest.approx(np.zeros(3), abs=1e-12)  # the body at the origin
    ahead = quat_rotate(q, np.array([0.0, 1.0, 0.0]))  # its heading (+y) shows as +x
    assert ahead == pytest.approx(np.array([1.0, 0.0, 0.0]), abs=1e-12)
    q, p = world_pose(0.0, controls.CAMERA_POSITION, body, math.pi / 2)
    assert q == pytest.approx(np.array([1.0, 0, 0, 0])) and p == pytest.approx([-0.03, -0.04, 0])
    q, p = world_pose(10.0, controls.CAMERA_FIXED, body, math.pi / 2)
    assert p == pytest.approx(np.zeros(3))


def test_the_floor_patch_stays_under_the_insect_on_its_own_grid() -> None:
    from web.floor import FLOOR_CELL_M, FLOOR_SECTION_M, floor_centre, floor_lines

    points, colours = floor_lines(0.1, FLOOR_CELL_M, FLOOR_SECTION_M)
    assert points.shape == colours.shape == (42, 2, 3)  # 21 lines each way, 2 end points
    assert np.abs(points).max() == pytest.approx(0.1)
    # lines run along x or along y, at z = 0
    assert np.all(points[:, :, 2] == 0)
    assert np.all((points[:, 0, 0] == points[:, 1, 0]) | (points[:, 0, 1] == points[:, 1, 1]))
    # the darker lines are the ones through multiples of a section, and only those
    offset = np.where(points[:, 0, 0] == points[:, 1, 0], points[:, 0, 0], points[:, 0, 1])
    on_section = np.isclose(np.round(offset / FLOOR_SECTION_M) * FLOOR_SECTION_M, offset)
    dark = colours[:, 0, 0] < colours.max()
    assert np.array_equal(dark, on_section) and dark.sum() == 10
    # it stays while the body is near its centre: a walk along a section line (y = 0.025)
    # does not make it jump back and forth
    centre = np.zeros(2)
    for y in (0.024, 0.026, 0.024, 0.034):
        assert floor_centre(np.array([0.0, y, 0.01]), centre) is centre
    # further away it jumps by whole sections, so the lines under the insect stay in place
    at = floor_centre(np.array([0.126, -0.024, 0.01]), centre)
    assert at == pytest.approx([0.15, 0.0])
    assert np.allclose(np.round(at / FLOOR_SECTION_M) * FLOOR_SECTION_M, at)
    assert floor_centre(np.array([0.16, 0.0]), at) is at  # and then stays again
    # however far the body walks, the patch reaches at least 6.5 cm past it on every side
    for x in np.linspace(0.0, 1.0, 401):
        centre = floor_centre(np.array([x, 0.3 * x]), centre)
        assert np.abs(centre - [x, 0.3 * x]).max() <= 0.1 - 0.065 + 1e-12


def test_readouts_do_not_claim_keeping_up_while_paused() -> None:
    paused = Readouts(0.66, 1.0, 2.5, 0.66, "metachronal", 2.0, None, 1.2, 1.0, 30.0, "")
    paused = Readouts(**{**paused.__dict__, "playing": False})
    s = format_readouts(paused)
    assert s["status"] == "paused" and "keeping up" not in s["status"]
    assert s["real-time factor"].startswith("paused")
    slow = Readouts(0.66, 1.0, 2.5, 0.66, "metachronal", 2.0, 0.93, 1.2, 1.0, 30.0, "")
    assert format_readouts(slow)["status"].startswith("behind: 0.93x of 1x")
    late = Readouts(**{**slow.__dict__, "lag_s": 12.34})
    assert "12.3 s behind real time" in format_readouts(late)["status"]


def test_footfall_shows_the_chosen_window_with_legs_coloured_by_pair() -> None:
    from web.style import LEG_COLOURS, PAIR_COLOURS

    bars = [[(0.0, 2.9)] for _ in range(6)]
    svg = footfall_svg(bars, 3.0, 0.5)
    assert 'data-window-s="0.5"' in svg and "last 0.5 s" in svg
    # clipped to the window: each bar starts at t = 2.5, not 0
    assert svg.count('class="stance"') == 6
    # fore red (legs 1-2), middle blue (3-4), hind green (5-6); left a tint of right
    assert LEG_COLOURS[0] == PAIR_COLOURS[0] and LEG_COLOURS[2] == PAIR_COLOURS[1]
    assert LEG_COLOURS[4] == PAIR_COLOURS[2] and LEG_COLOURS[1] != LEG_COLOURS[0]
    for leg, colour in zip(("R1", "L1", "R2", "L2", "R3", "L3"), LEG_COLOURS, strict=True):
        assert f'data-leg="{leg}"' in svg and f'fill="{colour}"' in svg


def test_the_ramp_draws_its_path_per_direction() -> None:
    from web.bifurcation_svg import bifurcation_svg

    run = Run()
    run.add([(0.05, 1.9)], at(0.62))  # before the ramp
    log = D31Conditions()
    log.start_ramp(run)
    run.add([(0.1, 2.0), (0.2, 2.05)], at(0.62, ramp="down", param="beta"))
    run.add([(0.3, 2.1), (0.4, 2.2)], at(0.63, ramp="up", param="beta"))
    run.add([(0.5, 2.2)], at(0.64))  # the ramp ended
    log.note(run)
    assert [e.at.ramp for e in log.ramp_path(run)] == ["down", "down", "up", "up"]
    svg = bifurcation_svg(None, "", [], (0.64, 2.2), (0.55, 0.8), log.ramp_path(run))
    assert svg.count('class="ramp"') == 2
    assert 'data-direction="down"' in svg and 'data-direction="up"' in svg
    log.start_ramp(run)  # a new ramp: a new path
    assert log.ramp_path(run) == []
    log.clear()
    assert len(log) == 0
    up = at(0.6, ramp="up", param="beta")
    wrap = [D31Event(0.1, 6.2, up), D31Event(0.2, 0.1, at(0.61, ramp="up", param="beta"))]
    svg = bifurcation_svg(None, "", [], (0.6, None), (0.55, 0.8), wrap)
    assert svg.count('class="ramp"') == 2  # broken at the wrap: two dots, no line through pi


def test_the_caption_promises_nothing_reproduction_md_marks_as_missed() -> None:
    from pathlib import Path

    from web.caption import CAPTION

    repro = (Path(__file__).resolve().parents[2] / "docs" / "REPRODUCTION.md").read_text()
    tripod_missed = any("hysteresis" in line and "**no**" in line for line in repro.splitlines())
    if tripod_missed:  # today: the caption must say so, and must not invite "watch it jump"
        assert "no hysteresis" in CAPTION and "does not appear" in CAPTION
        assert "watch" not in CAPTION.lower() and "jump from" not in CAPTION
    else:  # the loop reproduced: the caption must stop saying it is missing
        assert "no hysteresis" not in CAPTION and "does not appear" not in CAPTION


def test_time_axes_never_show_negative_times_and_name_their_unit() -> None:
    """Early in a run (t = 2 s, a 30 s window) the axis used to run from -28 s."""
    import re

    from web.svg import time_window

    assert time_window(2.0, 30.0) == (0.0, 30.0)
    assert time_window(45.0, 30.0) == (15.0, 45.0)
    d = d31_svg([(1.0, 2.0)], 2.0, 30.0, "metachronal")
    f = footfall_svg([[(0.1, 0.2)], [], [], [], [], []], 0.3, 0.5)
    for svg in (d, f):
        ticks = [float(x) for x in re.findall(r'text-anchor="middle">(-?[0-9.]+)</text>', svg)]
        assert ticks and min(ticks) >= 0.0, ticks
        assert "t (s)" in svg


def test_a_turned_insect_is_explained_not_left_to_guess() -> None:
    """After a +-30 deg slope the body walked at heading 94 deg on flat ground with no word."""
    from web.readouts import heading_note

    assert heading_note(None) == "" and heading_note(4.0) == "" and heading_note(-15.0) == ""
    note = heading_note(94.0)
    assert "turned 94°" in note and "no steering" in note and "Reset" in note
    assert "turned -90°" in heading_note(270.0)
    r = Readouts(0.66, 1.0, 2.5, 0.66, "tripod", 3.0, 1.0, 1.2, 1.0, 30.0, "", heading_deg=94.0)
    assert "no steering" in format_readouts(r)["status"]


def test_exported_settings_load_back_and_a_bad_file_names_its_field() -> None:
    import json

    from sim_core.contract import ModelChoice, Ramp, RunTemplate
    from web.export import Settings, load_settings, made_by, settings_json

    s = Settings(
        run=RunTemplate(body_mass_g=4.5, slope_deg=-7.5, phase_reset=False, integrator="rk4",
                        dt_s=1e-4),
        beta=0.62, d31_init=3.0, speed=None, time_s=12.0,
        ramp=Ramp("beta", 0.70, 0.62, 5.0, 20.0), ramp_running=False, ramp_started_at_s=None,
        job_duration_s=45.0, api_url="http://h:1",
        model=ModelChoice(ground="penalty", setting="soft_legs",
                          params={"ground_stiffness": 1000.0}),
    )  # fmt: skip
    made = made_by(s.choice())
    back = load_settings(settings_json(s, made=made))
    assert (back.beta, back.body_mass_g, back.slope_deg, back.d31_init) == (0.62, 4.5, -7.5, 3.0)
    assert back.speed is None and back.ground == "penalty" and back.ramp == s.ramp
    assert back.run == s.run  # every field of the run, phase_reset and the numerics too
    assert back.choice() == s.choice()  # the model parameters come back too
    # ... and go into every job body the file offers
    bodies = json.loads(settings_json(s, made=made))["jobs"]
    assert {k: bodies["run"][k] for k in ("ground", "setting", "params")} == {
        "ground": "penalty",
        "setting": "soft_legs",
        "params": {"ground_stiffness": 1000.0},
    }
    assert bodies["hysteresis"]["params"] == {"ground_stiffness": 1000.0}
    for body in bodies.values():  # ... and so does every field of the run
        assert body | s.run.model_dump() == body
    assert (back.job_duration_s, back.api_url) == (45.0, "http://h:1")
    raw = json.loads(settings_json(s, made=made))
    for key, value, words in (
        ("beta", 0.9, "beta: 0.9 is outside 0.55..0.8"),
        ("body_mass_g", "heavy", "body_mass_g: a number is expected"),
        ("speed", 3, 'speed: a multiple of real time .* or "max", the file has 3'),
        ("speed", "1x", 'write 1, a number, not "1x"'),
        ("ground", "ice", "ground: one of"),
        ("ramp", {"param": "beta"}, "ramp: param, start, turn"),
        ("params", {"kp_lifts": 1.0}, "params: unknown model parameter 'kp_lifts'"),
        ("params", {"kp_lift": -1.0}, "params: kp_lift: Input should be greater than 0"),
        ("setting", "stiff", "setting: no model setting 'stiff'"),
        ("ground", "constraint", "ground_stiffness is a parameter of the penalty ground only"),
        ("phase_reset", "no", "phase_reset: Input should be a valid boolean"),
        ("control_dt_s", 1e-5, r"control_dt_s \(1e-05\) must be >= dt_s"),  # RunSpec's rule
    ):
        with pytest.raises(ValueError, match=words):
            load_settings(json.dumps(raw | {key: value}).encode())
    with pytest.raises(ValueError, match="not JSON"):
        load_settings(b"beta,0.62\n")


# A settings file as the viewer wrote it before the file held the whole run template (beta, mass,
# slope and start by hand; the model choice; the job bodies of then).
OLD_FILE = """{"beta": 0.62, "body_mass_g": 4.5, "slope_deg": -7.5, "d31_init": 3.0, "speed": "max",
 "time_s": 12.0, "ramp": {"param": "beta", "start": 0.7, "turn": 0.62, "hold_s": 5.0,
 "ramp_s": 20.0}, "ramp_running": false, "ramp_started_at_s": null, "job_duration_s": 45.0,
 "api_url": "http://h:1", "ground": "penalty", "setting": null, "params": {"kp_lift": 0.001},
 "provenance": {"physics_version": "x", "params_hash": "y", "ground": "penalty", "dt_s": 5e-05,
 "params": "{}"}, "jobs": {"run": {"kind": "run", "beta": 0.62, "body_mass_g": 4.5,
 "slope_deg": -7.5, "duration_s": 45.0, "d31_init": [3.0], "ground": "penalty",
 "include_series": true}}, "jobs_url": "http://h:1/v1/jobs"}"""


def test_a_settings_file_of_the_old_format_still_loads() -> None:
    """A field the old file lacks is at RunSpec's default; what it says comes back."""
    import json

    from sim_core.contract import RunTemplate
    from web.export import load_settings, run_job

    s = load_settings(OLD_FILE.encode())
    assert (s.beta, s.body_mass_g, s.slope_deg, s.d31_init, s.speed) == (0.62, 4.5, -7.5, 3.0, None)
    assert s.run == RunTemplate(body_mass_g=4.5, slope_deg=-7.5)  # the rest at the defaults
    assert s.spec() == RunSpec(beta=0.62, body_mass_g=4.5, slope_deg=-7.5, d31_init=3.0)
    assert (s.ground, s.model.params, s.job_duration_s, s.api_url) == (
        "penalty", {"kp_lift": 0.001}, 45.0, "http://h:1")  # fmt: skip
    assert s.ramp is not None and (s.ramp.param, s.ramp.turn) == ("beta", 0.62)
    # its run job is the old one's, with every field of the run the old one left to the API
    old_body = json.loads(OLD_FILE)["jobs"]["run"]
    assert run_job(s) == old_body | RunTemplate(body_mass_g=4.5, slope_deg=-7.5).model_dump() | {
        "params": {"kp_lift": 0.001}}  # fmt: skip


def test_the_d31_history_marks_what_a_person_changed_and_each_ramp_phase() -> None:
    from web.record import Mark

    rec = D31Conditions()
    run = Run()
    events = run.d31_events

    def walk(t0: float, n: int, at: Conditions) -> None:
        run.add([(t0 + 0.1 * k, 2.0) for k in range(n)], at)
        rec.note(run)

    base = Conditions(0.66, 3.0, 0.0)
    walk(0.0, 20, base)  # 0 .. 1.9 s
    walk(2.0, 3, Conditions(0.64, 3.0, 0.0))  # beta set at 2.0
    walk(2.3, 3, Conditions(0.62, 3.0, 0.0))  # 0.3 s later, typed on: one mark, its end
    walk(5.0, 10, Conditions(0.62, 4.5, 0.0))
    walk(8.0, 3, at(0.62, 4.5, ramp="hold", param="beta"))
    walk(8.3, 5, at(0.63, 4.5, ramp="up", param="beta"))  # 0.3 s later: a mark of its own
    walk(9.5, 5, at(0.64, 4.5, ramp="up", param="beta"))  # the ramp moving: no mark
    walk(12.0, 3, Conditions(0.62, 4.5, 0.0))
    assert [(round(m.time_s, 1), m.label) for m in rec.marks] == [
        (2.3, "β 0.620"),
        (5.0, "mass 4.50 g"),
        (8.0, "ramp β hold"),
        (8.3, "ramp β up"),
        (12.0, "ramp over"),
    ]
    svg = d31_svg(events, 12.5, None, "metachronal", rec.marks)
    assert svg.count('<line class="mark"') == 5 and "ramp β up" in svg
    # a short ramp's phases on a long history: lines all kept, labels never over each other
    crowded = [Mark(50.0 + 0.1 * k, f"ramp mass phase {k}", False) for k in range(6)]
    svg = d31_svg([(0.1 * k, 2.0) for k in range(800)], 80.0, None, "other", crowded)
    assert svg.count('<line class="mark"') == 6
    texts = re.findall(
        r'<text class="mark" x="([\d.]+)" y="([\d.]+)" text-anchor="(\w+)"[^>]*>([^<]*)<', svg
    )
    assert texts and len(texts) < 6 and texts[-1][3].endswith(f"+{6 - len(texts)}")
    spans = []
    for x, y, anchor, text in texts:
        width = CHAR_W * len(text)
        left = float(x) if anchor == "start" else float(x) - width
        spans.append((float(y), left, left + width))
    for a in spans:
        for b in spans:
            if a is not b and a[0] == b[0]:
                assert a[2] <= b[1] or b[2] <= a[1], (a, b)
    rec.clear()
    assert rec.marks == []


def test_legends_wrap_inside_the_panel() -> None:
    import html
    import re

    from web.bifurcation_svg import bifurcation_svg
    from web.svg import W

    svg = bifurcation_svg(None, "", [], (0.66, 2.0), (0.55, 0.80))
    words = re.findall(r'<text x="([\d.]+)" y="[\d.]+" [^>]*fill="#[0-9a-f]+">([^<]+)<', svg)
    assert len(words) >= 9  # every legend entry is drawn...
    for x, text in words:  # ...and ends inside the panel (5.2 units a character at size 9)
        assert float(x) + 5.2 * len(html.unescape(text)) <= W, (x, text)


def test_a_finished_jobs_delta31_is_drawn_beside_the_live_walk() -> None:
    from web.jobs import first_run_d31

    result = {"result": {"series": {"d31": [
        {"run": 0, "time_s": 0.1, "d31": 2.0}, {"run": 0, "time_s": 0.2, "d31": 2.1},
        {"run": 1, "time_s": 0.1, "d31": 3.0}]}}}  # fmt: skip
    series = first_run_d31(result)
    assert series == ((0.1, 2.0), (0.2, 2.1))
    assert first_run_d31({"result": {"runs": []}}) == ()
    svg = d31_svg([(0.1, 2.05)], 1.0, None, "metachronal", (), ("abc123", series))
    assert n_dots(svg, "job") == 2 and n_dots(svg) == 1 and "● job abc123" in svg
    assert "job" not in d31_svg([(0.1, 2.05)], 1.0, None, "metachronal")

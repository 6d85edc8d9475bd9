"""The viewer's loop with a real viser server: idle without a browser; presets and the ramp.

With no browser connected the viewer does not simulate; a client connecting resumes it.

A real websocket client (the protocol a browser speaks, with viser's version subprotocol)
connects, sends the camera message a browser sends first (viser counts a client as connected
from then on) and disconnects, so viser's own connect/disconnect hooks drive the loop.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import msgspec.msgpack
import pytest
import viser
from viser._messages import ViewerCameraMessage
from websockets.sync.client import connect
from websockets.sync.connection import Connection

from sim_core.contract import METACHRONAL, TRIPOD
from web.app import ViewerApp


def _until(cond: Callable[[], bool], timeout_s: float, ws: Connection | None = None) -> bool:
    """Wait for `cond` (reading the client's messages meanwhile so the server never blocks)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if cond():
            return True
        if ws is not None:
            try:
                ws.recv(timeout=0.1)
            except TimeoutError:
                pass
        else:
            time.sleep(0.1)
    return cond()


def test_the_viewer_steps_only_while_a_client_is_connected() -> None:
    app = ViewerApp("127.0.0.1", 0)
    app.start()
    try:
        time.sleep(1.5)  # long enough for many frames, had the loop been stepping
        assert app.stats.idle and app.stats.clients == 0
        assert app.stats.sim_s == 0.0 and app.stats.frames == 0

        url = f"ws://127.0.0.1:{app.port}"
        with connect(url, subprotocols=[f"viser-v{viser.__version__}"]) as ws:  # type: ignore[list-item]
            camera = ViewerCameraMessage(
                wxyz=(1.0, 0.0, 0.0, 0.0),
                position=(0.0, -0.1, 0.05),
                fov=1.0,
                near=0.001,
                far=10.0,
                image_height=600,
                image_width=800,
                look_at=(0.0, 0.0, 0.0),
                up_direction=(0.0, 0.0, 1.0),
            )
            ws.send(msgspec.msgpack.encode(camera.as_serializable_dict()))
            assert _until(lambda: app.stats.sim_s > 0.05, 120, ws), "did not resume"
            assert not app.stats.idle and app.stats.clients == 1
        assert _until(lambda: app.stats.idle, 30), "did not pause when the client left"
        paused_at = app.stats.sim_s
        time.sleep(1.0)
        assert app.stats.sim_s == paused_at
    finally:
        app.stop()


def test_presets_and_the_ramp_drive_the_running_simulation() -> None:
    """The loop's request handling, called here with the loop not started (one thread)."""
    import math

    from web import controls
    from web.requests import Reset, StartRamp

    app = ViewerApp("127.0.0.1", 0)
    try:
        for preset in (TRIPOD, METACHRONAL):
            app.apply(Reset(preset))
            app.step(0.25, time.perf_counter() + 600)
            first = app.state.sim.d31_events[0][1]
            assert abs(first - preset) < 0.15, (preset, first)  # the first touchdowns start there
        app.apply(StartRamp(controls.make_ramp("beta", 0.66, 0.60, 0.0, 1.0)))
        app.step(0.6, time.perf_counter() + 600)
        assert app.state.ramp is not None and app.state.sim.beta < controls.BETA.initial
        path = app.state.d31_conditions.ramp_path(app.state.sim)
        assert path and {e.at.ramp for e in path} == {"down"}
        assert all(math.isfinite(e.d31) for e in path)
        assert path[-1].at.beta < path[0].at.beta  # the path follows beta down as it goes
        # the path is the core's own events, with the beta the loop set when each happened
        assert [(e.time_s, e.d31) for e in path] == app.state.sim.d31_events[-len(path) :]
    finally:
        app.stop()


def test_the_footfall_bars_are_the_stance_read_at_every_control_period() -> None:
    """The footfall diagram is drawn from `Simulation`'s own record (one sample per control
    period; a swing of ~34 ms spans ~68 of them): stepping one control period at a time and
    reading `sim.stance` directly, every sample in the diagram's window lies inside a drawn bar
    of its leg exactly when that leg was in stance, and the panel shows those bars."""
    from web.footfall_svg import footfall_svg
    from web.record import footfall_bars

    app = ViewerApp("127.0.0.1", 0)
    try:
        sim, window = app.state.sim, app.state.footfall_window_s
        direct = []
        while sim.time_s < window + 0.05:
            sim.advance(sim.control_dt_s)
            direct.append((sim.time_s, sim.stance.copy()))
        bars = footfall_bars(sim, window)
        t0 = sim.time_s - window
        seen = [(t, on) for t, on in direct[:-1] if t >= t0]  # the last sample ends the bars
        assert len(seen) > 0.9 * window / sim.control_dt_s
        for t, on in seen:
            for leg in range(6):
                inside = any(a <= t < b for a, b in bars[leg])
                assert inside == on[leg], (t, leg, bars[leg])
        # a leg in stance at the window's edge has a bar from the edge (the diagram clips it)
        first = max(i for i, (t, _) in enumerate(direct) if t <= t0)
        for leg in range(6):
            if direct[first][1][leg]:
                assert any(a <= t0 < b for a, b in bars[leg]), (leg, bars[leg])
        assert sum(map(len, bars)) >= 6  # a few steps per leg: the check saw transitions
        app.painter.gait()
        assert app.panels.footfall.content == footfall_svg(bars, sim.time_s, window)
    finally:
        app.stop()


def test_a_reset_starts_the_record_and_its_panels_over_and_an_idle_plot_is_not_rebuilt() -> None:
    from web.requests import Reset

    app = ViewerApp("127.0.0.1", 0)
    try:
        app.step(0.3, time.perf_counter() + 600)
        app.painter.gait()
        assert 'class="stance"' in app.panels.footfall.content
        n = len(app.state.sim.d31_events)
        assert n > 0 and len(app.state.d31_conditions) == n
        assert f'data-n-events="{n}"' in app.panels.d31.content
        # nothing stepped, nothing changed: the panels are not rebuilt
        app.panels.footfall.content = "idle"
        app.panels.d31.content = "idle"
        app.painter.gait()
        assert app.panels.footfall.content == app.panels.d31.content == "idle"
        app.apply(Reset(2.0))
        assert (
            app.state.sim.time_s == 0.0
            and len(app.state.sim.d31_events) == len(app.state.d31_conditions) == 0
        )
        app.painter.gait()  # a new walk: redrawn, empty
        assert 'class="stance"' not in app.panels.footfall.content
        assert 'data-n-events="0"' in app.panels.d31.content
        app.step(0.05, time.perf_counter() + 600)
        times, _ = app.state.sim.footfall_since(None)
        assert times[0] < 0.05 and len(app.state.d31_conditions) == len(app.state.sim.d31_events)
        app.painter.gait()
        assert app.panels.footfall.content != "idle"
    finally:
        app.stop()


def test_a_mass_ramp_holds_ramps_and_holds_and_the_export_shows_it() -> None:
    """The core's Ramp drives body mass from the loop: hold, up, down, hold, then the ramp
    ends at its start; the Delta31 export carries the mass in force at every touchdown."""
    import csv
    import io

    from web import controls
    from web.requests import Export, SetParam, StartRamp

    app = ViewerApp("127.0.0.1", 0)
    try:
        app.step(0.2, time.perf_counter() + 600)
        ramp = controls.make_ramp("body_mass_g", 3.0, 5.0, 0.3, 0.4)
        app.apply(StartRamp(ramp))
        app.apply(SetParam("body_mass_g", 9.0))  # its slider is disabled: a stale request
        t0 = app.state.sim.time_s
        app.step(ramp.duration_s + 0.1, time.perf_counter() + 600)
        assert app.state.ramp is None and app.state.sim.body_mass_g == 3.0
        got: list[tuple[str, bytes]] = []
        app.apply(Export("d31", lambda name, data: got.append((name, data))))
        rows = list(csv.DictReader(io.StringIO(got[0][1].decode())))
        during = [r for r in rows if r["ramp"]]
        # each row names the ramped parameter and its phase, the values rounded to 1e-6
        assert {r["ramp"] for r in during} == {f"body_mass_g {p}" for p in ("hold", "up", "down")}
        assert all(len(r["body_mass_g"].split(".")[-1]) <= 6 for r in during)
        for r in during:
            expected = ramp.value(float(r["time_s"]) - t0)
            assert abs(float(r["body_mass_g"]) - expected) < 0.05, r  # within one chunk
        assert max(float(r["body_mass_g"]) for r in during) > 4.5
    finally:
        app.stop()


def test_the_ground_button_restarts_the_walk_on_the_papers_ground_where_it_stood() -> None:
    """Issue 30: slopes must be walked up and down; the paper's ground keeps the heading."""
    import json

    from web import controls
    from web.requests import Export, SetGround, SetParam

    app = ViewerApp("127.0.0.1", 0)
    try:
        app.apply(SetParam("slope_deg", -20.0))
        app.step(0.2, time.perf_counter() + 600)
        old = app.state.sim
        app.apply(SetGround("penalty"))
        assert app.state.sim is not old and app.state.ground == "penalty"
        assert app.state.sim.slope_deg == -20.0 and app.state.sim.time_s == 0.0  # kept; a new walk
        assert len(app.state.sim.d31_events) == len(app.state.d31_conditions) == 0
        app.step(0.3, time.perf_counter() + 600)
        sim = app.state.sim
        assert sim.error is None and len(app.state.d31_conditions) == len(sim.d31_events) > 0
        app.apply(SetGround("penalty"))  # the same ground again: no restart
        assert app.state.sim.time_s > 0.0
        got: list[tuple[str, bytes]] = []
        app.apply(Export("settings", lambda name, data: got.append((name, data))))
        settings = json.loads(got[0][1])
        assert settings["ground"] == "penalty" and settings["jobs"]["run"]["ground"] == "penalty"
        with pytest.raises(ValueError, match="unknown ground"):
            app.apply(SetGround("ice"))
        assert set(controls.GROUNDS.values()) == {"constraint", "penalty"}
    finally:
        app.stop()


def test_model_parameters_survive_a_ground_switch_and_reach_the_exports() -> None:
    """Issue 53: the walk's non-default parameters (`--param`) are shown, kept by the ground
    switch (one the other ground lacks refuses it), and carried by the export and job body;
    the new simulation keeps every field of the walk's spec, not four of them."""
    import json

    from sim_core.contract import ModelChoice, RunSpec
    from web.requests import Export, SetGround

    spec = RunSpec(beta=0.66, d31_init=2.0, phase_reset=False)
    app = ViewerApp("127.0.0.1", 0, spec=spec, model=ModelChoice(params={"kp_lift": 1e-3}))
    try:
        assert app.state.sim._runner.params.leaf("kp_lift") == 1e-3
        assert app.state.model_words == "kp_lift 0.001"
        app.apply(SetGround("penalty"))
        assert app.state.ground == "penalty" and app.state.model_words == "kp_lift 0.001"
        assert app.state.sim._runner.params.leaf("kp_lift") == 1e-3
        assert app.state.sim._runner.params.contact.ground == "penalty"
        assert app.state.sim._spec.phase_reset is False  # kept across the switch
        got: list[tuple[str, bytes]] = []
        app.apply(Export("settings", lambda name, data: got.append((name, data))))
        settings = json.loads(got[0][1])
        assert settings["params"] == settings["jobs"]["run"]["params"] == {"kp_lift": 1e-3}
        assert json.loads(settings["provenance"]["params"]) == {"kp_lift": 1e-3}
        penalty = ModelChoice(ground="penalty", params={"ground_stiffness": 1000.0})
        app.state.restart(2.0, model=penalty)
        with pytest.raises(ValueError, match="ground_stiffness is a parameter of the penalty"):
            app.apply(SetGround("constraint"))
        assert app.state.model == penalty  # refused: the walk is as it was
    finally:
        app.stop()


def test_paused_the_walk_steps_one_gait_cycle_at_a_time() -> None:
    """Issue 42 point 10: a single step, as mujoco's viewer has; it does nothing while playing."""
    from web.requests import SetPlaying, StepCycle

    app = ViewerApp("127.0.0.1", 0)
    try:
        app.step(0.2, time.perf_counter() + 600)
        app.apply(StepCycle())  # playing: ignored (the loop is stepping anyway)
        assert app.state.sim.time_s == pytest.approx(0.2, abs=0.003)
        app.apply(SetPlaying(False))
        t0, n0 = app.state.sim.time_s, len(app.state.sim.d31_events)
        app.apply(StepCycle())
        period = 0.034 / (1.0 - app.state.sim.beta)  # T_sw / (1 - beta)
        assert app.state.sim.time_s - t0 == pytest.approx(period, abs=0.003)
        # leg 1 lands once a cycle (twice if the cycle's ends straddle two touchdowns)
        assert 1 <= len(app.state.sim.d31_events) - n0 <= 2
        assert len(app.state.d31_conditions) == len(app.state.sim.d31_events)
        assert not app.state.playing
    finally:
        app.stop()


def test_a_restart_with_other_run_fields_builds_a_new_simulation_only_then() -> None:
    """A loaded file's run (`restart(run=...)`): a field the walk does not have (phase resetting
    off) builds a new simulation of it; the same fields restart the one there."""
    from sim_core.contract import RunTemplate
    from web.state import ViewerState

    state = ViewerState.of()
    first = state.sim
    state.restart(2.0, run=RunTemplate.of(state.now()))
    assert state.sim is first and state.spec.phase_reset
    state.restart(2.5, run=RunTemplate(phase_reset=False))
    assert state.sim is not first and state.spec.phase_reset is False
    assert (state.spec.d31_init, state.sim.beta) == (2.5, first.beta)


def test_loaded_settings_restart_the_walk_where_the_file_says() -> None:
    from dataclasses import replace

    from sim_core.contract import ModelChoice, Ramp
    from web.export import load_settings, settings_json
    from web.requests import LoadSettings

    app = ViewerApp("127.0.0.1", 0)
    try:
        app.step(0.05, time.perf_counter() + 600)
        now = app.state.settings(app.panels.job_inputs())
        assert now.run.spec().phase_reset  # the walk resets its phases; the file says not
        run = now.run.replace(body_mass_g=4.5, slope_deg=5.0, phase_reset=False)
        saved = replace(
            now, run=run, beta=0.62, d31_init=3.0, speed=None, model=ModelChoice(ground="penalty"),
            ramp=Ramp("body_mass_g", 3.0, 6.0, 2.0, 10.0), job_duration_s=45.0,
        )  # fmt: skip
        walked = app.state.sim
        app.apply(LoadSettings(load_settings(settings_json(saved, made=app.state.provenance()))))
        sim = app.state.sim
        assert (sim.beta, sim.body_mass_g, sim.slope_deg, sim.time_s) == (0.62, 4.5, 5.0, 0.0)
        # every field of the file's run reaches the walk, and the next export
        assert sim is not walked and app.state.spec.phase_reset is False  # a new simulation
        assert app.state.settings(app.panels.job_inputs()).run == run
        assert (app.state.ground, app.state.d31_init, app.state.speed) == ("penalty", 3.0, None)
        assert app.panels.ramp.param_name == "body_mass_g" and app.panels.ramp.turn.value == 6.0
        assert (
            app.panels.job_duration.value == 45.0 and app.state.ramp is None
        )  # set up, not started
        app.painter.readouts(None, None, None)
        beta = app.panels.walk.live["beta"]
        assert beta.value == beta.box.value == 0.62  # slider and box show what was loaded
        assert app.panels.walk.speed.label == "speed — max"
        assert app.panels.walk.ground.label == "ground — penalty"
        assert app.panels.ramp.param.label == "ramp drives — body mass (g)"
    finally:
        app.stop()

"""The start buttons move their slider: "Start as tripod" restarts from pi and the initial
Delta31 slider then says 3.14, so "Reset with this initial Δ31" restarts from the same start
(it used to stay at 2.09 and restart the metachronal gait)."""

from __future__ import annotations

import math
import time

from sim_core.contract import METACHRONAL, TRIPOD
from web.app import ViewerApp
from web.requests import Reset


def test_the_start_buttons_move_the_initial_delta31_slider() -> None:
    app = ViewerApp("127.0.0.1", 0)
    try:
        assert app.panels.walk.d31_init.value == round(METACHRONAL, 2)
        app.apply(Reset(TRIPOD))
        assert app.state.d31_init == TRIPOD and app.panels.walk.d31_init.value == 3.14
        app.step(0.05, time.perf_counter() + 600)
        app.apply(Reset(float(app.panels.walk.d31_init.value)))  # "Reset with this initial Δ31"
        assert math.isclose(app.state.d31_init, 3.14) and app.state.sim.time_s == 0.0
        app.apply(Reset(METACHRONAL))
        assert app.panels.walk.d31_init.value == 2.09
    finally:
        app.stop()

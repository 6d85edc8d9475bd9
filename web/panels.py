"""The control panel: sliders and buttons that only queue requests, readouts and diagrams.

Every callback here runs on viser's thread pool and does one thing: put a request on the queue.
When the loop thread sets a control itself (the ramp moving the beta slider, the play button's
label), viser calls the same callbacks synchronously with `event.client is None`; those echoes
are ignored, so the loop never queues requests to itself.

All browsers see the same panel (`server.gui` state is shared), which is why there is one
simulation for everyone (docs/VIEWER.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import viser

from web import controls
from web.requests import (
    RequestQueue,
    Reset,
    SetBeta,
    SetBodyMass,
    SetFollow,
    SetPlaying,
    SetSlope,
    SetSpeed,
    StartRamp,
    StopRamp,
)

PLAY, PAUSE = "Play", "Pause"
RAMP_START, RAMP_STOP = "Ramp β down and up", "Stop ramp"


@dataclass(frozen=True)
class Readouts:
    """What the loop measured; `format_readouts` turns it into the panel's strings."""

    beta: float
    time_s: float
    speed_cm_s: float | None
    duty_factor: float | None
    gait: str
    d31_now: float
    rtf: float | None
    stepping_rtf: float | None
    target_speed: float | None  # None: as fast as possible
    frame_hz: float | None
    ramp: str  # "" when no ramp runs, else "down"/"up" and the ramp's beta
    error: str | None = None


def _f(v: float | None, fmt: str, missing: str = "–") -> str:
    return missing if v is None or not math.isfinite(v) else fmt.format(v)


def format_readouts(r: Readouts) -> dict[str, str]:
    """Panel strings, keyed by readout label. Pure, so a test pins what a user reads."""
    if r.error:
        status = f"stopped: {r.error} — press Reset"
    elif r.target_speed is None:
        status = "running as fast as possible"
    elif r.rtf is not None and r.rtf < 0.9 * r.target_speed:
        status = f"behind: {r.rtf:.2f}x of {r.target_speed:g}x (machine too slow)"
    else:
        status = f"keeping up with {r.target_speed:g}x"
    return {
        "β (simulation)": f"{r.beta:.4f}",
        "sim time (s)": f"{r.time_s:.2f}",
        "speed (cm/s)": _f(r.speed_cm_s, "{:.2f}"),
        "duty factor (measured)": _f(r.duty_factor, "{:.3f}"),
        "gait": f"{r.gait}  (Δ31 now {r.d31_now:.2f} rad)",
        "real-time factor": _f(r.rtf, "{:.2f}x")
        + f"  (stepping alone {_f(r.stepping_rtf, '{:.1f}x')})",
        "stream rate (Hz)": _f(r.frame_hz, "{:.0f}"),
        "ramp": r.ramp or "off",
        "status": status,
    }


class Panels:
    """Builds the GUI once; the loop thread calls the `show_*`/`sync_*` methods."""

    def __init__(self, server: viser.ViserServer, requests: RequestQueue) -> None:
        self.server = server
        self.requests = requests
        gui = server.gui
        gui.configure_theme(control_width="large", dark_mode=False)
        gui.add_markdown(
            "**Hexapod (Fujiki et al. 2013)** — drag β down and watch the gait jump from "
            "metachronal to tripod; ramp β to draw the hysteresis loop."
        )
        with gui.add_folder("Controls"):
            self.beta = self._slider(controls.BETA, lambda v: SetBeta(controls.beta_value(v)))
            self.mass = self._slider(
                controls.BODY_MASS_G, lambda v: SetBodyMass(controls.body_mass_g_value(v))
            )
            self.slope = self._slider(
                controls.SLOPE_DEG, lambda v: SetSlope(controls.slope_deg_value(v))
            )
            self.speed = gui.add_dropdown(
                "speed", tuple(controls.SPEEDS), initial_value=controls.DEFAULT_SPEED
            )
            self.speed.on_update(
                self._queue(lambda: SetSpeed(controls.speed_value(self.speed.value)))
            )
            self.play = gui.add_button(PAUSE)
            self.play.on_click(self._on_play)
            self._playing = True
            self.d31_init = self._slider(controls.D31_INIT, None)
            self.reset = gui.add_button("Reset with this initial Δ31")
            self.reset.on_click(
                self._queue(lambda: Reset(controls.d31_init_value(self.d31_init.value)))
            )
            self.ramp_rate = gui.add_number(
                "ramp rate (β/s)", 0.004, min=0.0005, max=0.05, step=0.0005
            )
            self.ramp = gui.add_button(RAMP_START)
            self.ramp.on_click(self._on_ramp)
            self._ramping = False
            self.follow = gui.add_checkbox("follow camera", True)
            self.follow.on_update(self._queue(lambda: SetFollow(bool(self.follow.value))))
        with gui.add_folder("Readouts"):
            blank = format_readouts(
                Readouts(
                    controls.BETA.initial, 0.0, None, None, "–", 0.0, None, None, 1.0, None, ""
                )
            )
            self.readouts = {k: gui.add_text(k, v, disabled=True) for k, v in blank.items()}
        with gui.add_folder("Plots"):
            self.footfall = gui.add_html("<em>footfall: waiting for the first steps</em>")
            self.d31 = gui.add_html("<em>Δ31: waiting for leg-1 touchdowns</em>")
            self.bifurcation = gui.add_html("<em>bifurcation diagram</em>")
        self._last: dict[str, str] = {}

    # --- callbacks: queue only -----------------------------------------------------------------
    def _slider(self, spec: controls.SliderRange, make: Any) -> viser.GuiSliderHandle:
        label = f"{spec.label} ({spec.unit})" if spec.unit else spec.label
        handle = self.server.gui.add_slider(
            label, min=spec.lo, max=spec.hi, step=spec.step, initial_value=spec.initial
        )
        if make is not None:
            handle.on_update(self._queue(lambda: make(handle.value)))
        return handle

    def _queue(self, make: Any) -> Any:
        def callback(event: viser.GuiEvent) -> None:
            if event.client is None:
                return  # the loop set this control itself: not a user's request
            self.requests.put(make())

        return callback

    def _on_play(self, event: viser.GuiEvent) -> None:
        if event.client is not None:
            self.requests.put(SetPlaying(not self._playing))

    def _on_ramp(self, event: viser.GuiEvent) -> None:
        if event.client is None:
            return
        if self._ramping:
            self.requests.put(StopRamp())
        else:
            self.requests.put(StartRamp(float(self.ramp_rate.value)))

    # --- loop thread only ----------------------------------------------------------------------
    def sync_controls(self, beta: float | None, playing: bool, ramping: bool) -> None:
        """Reflect state the loop changed (ramp beta, play state) without queueing requests."""
        if beta is not None and abs(self.beta.value - beta) > 1e-9:
            self.beta.value = beta
        if playing != self._playing:
            self._playing = playing
            self.play.label = PAUSE if playing else PLAY
        if ramping != self._ramping:
            self._ramping = ramping
            self.ramp.label = RAMP_STOP if ramping else RAMP_START

    def show_readouts(self, r: Readouts) -> None:
        for label, text in format_readouts(r).items():
            if self._last.get(label) != text:
                self._last[label] = text
                self.readouts[label].value = text

    def show_html(self, handle: viser.GuiHtmlHandle, content: str) -> None:
        if handle.content != content:
            handle.content = content

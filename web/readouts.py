"""The readouts and the status line: what the loop measured, as the strings a person reads.

Pure (numbers in, strings and markup out), so a test pins what a user reads; the panel
(web/panel_parts.py) shows them, the loop's painter (web/painter.py) fills them.
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass

from web import controls

# "behind" below this share of the chosen speed: the 1 s rate window reads 0.97-1.0 at 1x
# when all is well, so 0.95 is a real shortfall, not noise.
BEHIND_RATIO = 0.95


@dataclass(frozen=True)
class Readouts:
    """What the loop measured; `format_readouts` turns it into the panel's strings."""

    beta: float
    time_s: float
    speed_cm_s: float | None  # along the body's heading (`Simulation.speed_cm_s`)
    duty_factor: float | None
    gait: str
    d31_now: float
    rtf: float | None
    stepping_rtf: float | None
    target_speed: float | None  # None: as fast as possible
    frame_hz: float | None
    ramp: str  # "" when no ramp runs, else "down"/"up" and the ramp's beta
    error: str | None = None
    playing: bool = True
    body_mass_g: float = controls.BODY_MASS_G.initial
    slope_deg: float = controls.SLOPE_DEG.initial
    heading_deg: float | None = None
    ground: str = "constraint"
    model: str = "defaults"  # the model parameters off their defaults (`ModelChoice.words`)
    lag_s: float = 0.0  # simulated seconds the walk is behind the wall clock at this speed


# A heading this far from +x (the slope's uphill direction) gets a word of explanation.
TURNED_DEG = 20.0


def heading_note(heading_deg: float | None) -> str:
    """Why the insect walks off +x after a slope turned it, or "" while it has not turned.

    The model (as the paper's) has no steering: each leg's stance line is fixed in the body,
    so a slope that yaws the body leaves it walking the new way when the slope is gone."""
    if heading_deg is None:
        return ""
    off = (heading_deg + 180.0) % 360.0 - 180.0
    if abs(off) < TURNED_DEG:
        return ""
    return (
        f"turned {round(off)}° from the slope's +x: the model has no steering (nor has the "
        "paper's), so it keeps walking the way a slope yawed it; Reset faces it uphill again, "
        "and the penalty ground, the paper's (button 'ground'), keeps its heading on slopes"
    )


def _f(v: float | None, fmt: str, missing: str = "–") -> str:
    return missing if v is None or not math.isfinite(v) else fmt.format(v)


def format_readouts(r: Readouts) -> dict[str, str]:
    """Panel strings, keyed by readout label. Pure, so a test pins what a user reads."""
    if r.error:
        status = f"stopped: {r.error} — press Reset"
    elif not r.playing:
        status = "paused"
    elif r.target_speed is None:
        status = "running as fast as possible" + _f(r.rtf, " ({:.2f}x)", "")
    elif r.rtf is None:
        status = "starting"
    elif r.rtf < BEHIND_RATIO * r.target_speed:
        # other work on the cores (API jobs), or a speed above what stepping alone reaches
        status = (
            f"behind: {r.rtf:.2f}x of {r.target_speed:g}x, {r.lag_s:.1f} s behind real time "
            "(machine cannot keep up)"
        )
    else:
        status = f"keeping up with {r.target_speed:g}x"
    turned = heading_note(r.heading_deg)
    if turned and not r.error:
        status += f"; {turned}"
    rtf = "paused" if not r.playing else _f(r.rtf, "{:.2f}x")
    return {
        "β (simulation)": f"{r.beta:.4f}",
        "body mass (simulation, g)": f"{r.body_mass_g:.2f}",
        "slope (simulation, °)": f"{r.slope_deg:.1f}",
        "ground": controls.GROUND_LABEL[r.ground],
        # which model parameters are not the defaults (`--setting`, `--param`, a loaded file)
        "model": r.model,
        "sim time (s)": f"{r.time_s:.2f}",
        "speed along heading (cm/s)": _f(r.speed_cm_s, "{:.2f}")
        + ("" if r.heading_deg is None else f"  (heading {round(r.heading_deg)}°)"),
        "duty factor (measured)": _f(r.duty_factor, "{:.3f}"),
        # the gait walked over the last touchdowns (`Simulation.gait`), not a settled verdict
        "gait now": f"{r.gait}  (Δ31 now {r.d31_now:.2f} rad)",
        "real-time factor": rtf + f"  (stepping alone {_f(r.stepping_rtf, '{:.1f}x')})",
        "stream rate (Hz)": _f(r.frame_hz, "{:.0f}"),
        "ramp": r.ramp or "off",
        "status": status,
    }


def note_html(text: str, *, error: bool = False) -> str:
    """A one-line note under a control (what a load did, or why it did not)."""
    colour = "#b00" if error else "#555"
    return (
        f'<div data-note style="font-size:0.8em;color:{colour};overflow-wrap:anywhere">'
        f"{html.escape(text)}</div>"
    )


def status_html(status: str) -> str:
    """The status line in a box that wraps (a ~230-character status used to be clipped in a
    one-line text input)."""
    return (
        '<div data-readout="status" style="white-space:normal;overflow-wrap:anywhere;'
        'font-size:0.8em;line-height:1.3;padding:2px 0">'
        f"<b>status:</b> {html.escape(status)}</div>"
    )

"""The control panel's words: its buttons' and boxes' labels and the HTML lines it shows.

Their own module because the panel (web/panels.py) and its parts, the browser tests and the
benchmarks all find a control by its label: one definition each, imported wherever a control is
looked for; and how a browser reads a control by its label (the JavaScript the end-to-end tests
and the benchmarks evaluate in the page, `READ_BY_LABEL`, `TAG_BY_LABEL`), kept next to the
labels whose markup it depends on.
"""

PLAY, PAUSE = "Play", "Pause"
STEP = "Step one cycle"
SUBMIT_RUN, SUBMIT_RAMP = "Submit as a run job", "Submit the ramp as a hysteresis job"
OPEN_JOB = "Open job by id"
LIVE_AGAIN = "Back to the live walk"  # ends a job's replay in the panels (web/job_panel.py)
RAMP_PLOT_EMPTY = "<em>a ramp's path: Δ31 against what it ramps</em>"


def cancel_label(job_id: str) -> str:
    """A job row's cancel button: the job's short id tells the rows apart."""
    return f"Cancel job {job_id[:8]}".strip()


def replay_label(job_id: str) -> str:
    """A job row's replay button (a done run or hysteresis job)."""
    return f"Replay job {job_id[:8]} in the panels".replace("  ", " ")


LOAD_SETTINGS = "Load settings (JSON)"
DRAW_3D = "draw the 3D walk"
DRAW_3D_HINT = (
    "Off: the 3D view holds its last pose and the simulation gets the core a browser without a "
    "GPU spends drawing it; the plots and readouts stay live."
)


def view_cost_html(software_fps: float) -> str:
    """The line under "draw the 3D walk": what a browser without a GPU gets, and its choices.

    Such a browser draws the 3D view at most `software_fps` frames a second (web/frame_cap.py);
    `?frameCap=0` draws every frame. viser reads a fixed device-pixel ratio from the URL (its
    `fixedDpr` dev setting): at half resolution a frame costs ~20% less CPU (23 against 29
    ms here), so the capped page takes less and the uncapped one draws more. Links, not
    defaults: on a GPU every frame at full resolution costs nothing.
    """
    then = (
        f"then draws {software_fps:g} frames a second" if software_fps > 0 else "draws every frame"
    )
    return (
        '<div style="font-size:0.75em;padding-left:0.5em">No GPU (software WebGL)? The 3D view '
        f"{then}: "
        '<a href="?fixedDpr=0.5">the 3D view at half resolution</a> · '
        '<a href="?frameCap=0">every frame</a> · <a href="?">default</a></div>'
    )


RAMP_START, RAMP_STOP = "Start ramp", "Stop ramp"
# export buttons: label -> what (web/export.py)
EXPORT_BUTTONS = {
    "Δ31 trace (CSV)": "d31",
    "footfall (CSV)": "footfall",
    "ramp path (CSV)": "ramp",
    "settings (JSON)": "settings",
}
D31_WINDOW_LABEL = "Δ31 window (s, 0 = whole run)"
PRESET_TRIPOD, PRESET_METACHRONAL = "Start as tripod (Δ31 = π)", "Start as metachronal (2π/3)"
# the drift-surface panel's offer when no surface of the walk's conditions exists (web/surfaces.py)
COMPUTE_SURFACE = "Compute the drift surface for these conditions"

# The value of the text input next to the control labelled `label` (for a slider: its number
# box), or null when no such label is on the page.
READ_BY_LABEL = """label => {
  const l = [...document.querySelectorAll('label')].find(e => e.textContent.trim() === label);
  if (!l) return null;
  let node = l.parentElement;
  while (node && !node.querySelector('input:not([type=hidden])')) node = node.parentElement;
  return node ? node.querySelector('input:not([type=hidden])').value : null;
}"""

# Mark the text input next to the control labelled `label` with data-probe-box="tag", so that
# a locator can type into it (`[data-probe-box=tag]`).
TAG_BY_LABEL = """([label, tag]) => {
  const l = [...document.querySelectorAll('label')].find(e => e.textContent.trim() === label);
  let node = l.parentElement;
  while (node && !node.querySelector('input:not([type=hidden])')) node = node.parentElement;
  node.querySelector('input:not([type=hidden])').setAttribute('data-probe-box', tag);
}"""

"""How often a browser draws the 3D view: at most a few frames a second where it has no GPU.

Why. viser's client draws on demand, but each scene change opens a 250 ms window of continuous
frames (`RENDER_SETTLE_MS` in its App.tsx), so poses streamed at 30 Hz keep it drawing at the
display rate. A browser without a GPU draws WebGL in software (SwiftShader, llvmpipe) on the
CPU, 25-75 ms of a core per frame on a 2-core host (benchmarks/viewer_rtf.py): it then draws as
many frames as one core allows and takes that core from the simulation. So a page whose WebGL
renderer is a software one (the test viser's own warning uses) draws at most `software_fps`
frames a second; with a GPU it draws every frame. `?frameCap=N` in the page's URL asks for N
(0: every frame), per browser.

How. viser 1.1 replays a `RunJavascriptMessage` to every browser that connects (it keeps it in
the scene's state, as it does for plotly.js). Ours wraps `window.requestAnimationFrame`: the
callbacks asked for between two allowed frames run together at the next one, in order.
react-three-fiber asks for each frame through that global, so its render loop (and any other
animation on the page) runs unchanged, only less often. `window.__igFrameCap` says what the
page chose and counts the animation frames it let through, an upper bound of the 3D view's
(viser's one-second heartbeat and the page's own animations are frames too; the benchmark and
the browser tests read it).
"""

from __future__ import annotations

import json
import logging
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # `insect-gait viewer --help` reads SOFTWARE_FPS without importing viser
    import viser

from web.viser_private import NoHook, private_channel

log = logging.getLogger(__name__)

QUERY_KEY = "frameCap"  # the page's URL parameter: frames a second, 0 = every frame
# The cap where WebGL runs in software: every second pose of the 30 Hz stream, evenly spaced.
# Measured by `benchmarks/viewer_rtf.py --frame-caps 15,10,20,0 --rounds 3` (headless Chromium
# at 1280x800 drawing WebGL in software on a 2-core host; the walk at "max", 10 s windows, the
# cap set live in one page): a frame costs 28-32 ms of a core; capped at 15 the page drew 13.9
# frames a second, its GPU process took 0.40 of a core and the simulation stepped at 0.87
# (0.86-0.88) of `bench` single, against 31.7 frames, 0.86 of a core and 0.79 (0.78-0.80)
# drawing every frame, and 0.88 at a cap of 10 (later runs at 15: 0.84 on average, one window
# of 30 under 0.8; the tables are docs/VIEWER.md's).
SOFTWARE_FPS = 15.0
# The least cap but 0 (every frame): viser applies its messages in the render loop, so below one
# frame a second the readouts and the status line would stall with the 3D view.
MIN_FPS = 1.0

# `__AUTO__` becomes the cap for software renderers, `__MIN__` the least one; the rest is
# the page's own logic.
_SOURCE = """(() => {
  const w = window;
  if (w.__igFrameCap) return;  // replayed on a reconnect: wrapped once
  const software = /swiftshader|llvmpipe|softpipe|software/i.test((() => {
    try {
      const gl = document.createElement('canvas').getContext('webgl');
      if (!gl) return '';
      const info = gl.getExtension('WEBGL_debug_renderer_info');
      const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
      const lose = gl.getExtension('WEBGL_lose_context');
      if (lose) lose.loseContext();
      return name;
    } catch (e) { return ''; }
  })());
  const text = (new URLSearchParams(w.location.search).get('__KEY__') ?? '').trim();
  const asked = text === '' ? NaN : Number(text);  // absent or blank: the default
  const fps = !(Number.isFinite(asked) && asked >= 0) ? (software ? __AUTO__ : 0)
            : asked > 0 ? Math.max(__MIN__, asked) : 0;
  const cap = { fps: fps, software: software, frames: 0 };
  w.__igFrameCap = cap;
  const nativeRaf = w.requestAnimationFrame.bind(w);
  const nativeCancel = w.cancelAnimationFrame.bind(w);
  let queue = new Map(), nextId = 1e9, pending = false, last = -Infinity;
  const flush = t => {
    // a frame is due within a quarter of a 60 Hz frame; the timer wakes a frame early and
    // the browser's own frame clock picks the moment, so frames stay evenly spaced
    const wait = cap.fps > 0 ? 1000 / cap.fps - (t - last) : 0;
    if (wait > 4) { setTimeout(() => nativeRaf(flush), Math.max(0, wait - 17)); return; }
    pending = false;
    const due = queue; queue = new Map();
    if (due.size === 0) return;  // every callback was cancelled: no frame
    last = t; cap.frames++;
    // one callback that throws does not stop the others (as with the browser's own frames):
    // react-three-fiber's loop, and with it viser's message queue, must keep running
    for (const cb of due.values()) {
      try { cb(t); } catch (e) { setTimeout(() => { throw e; }); }
    }
  };
  w.requestAnimationFrame = cb => {
    const id = nextId++;
    queue.set(id, cb);
    if (!pending) { pending = true; nativeRaf(flush); }
    return id;
  };
  w.cancelAnimationFrame = id => { if (!queue.delete(id)) nativeCancel(id); };
})();"""


def frame_cap_source(software_fps: float) -> str:
    """The page's script, with the cap for software renderers filled in."""
    fill = {"__AUTO__": json.dumps(float(software_fps)), "__MIN__": json.dumps(MIN_FPS),
            "__KEY__": QUERY_KEY}  # fmt: skip
    source = _SOURCE
    for key, value in fill.items():
        source = source.replace(key, value)
    return source


def install_frame_cap(server: viser.ViserServer, software_fps: float) -> bool:
    """Send the script to every browser, now and as each connects.

    Returns False (and logs why) if this viser has no such message: the page then draws every
    frame, as before, and the viewer still works.
    """
    try:
        interface, (run_script,) = private_channel(server, "RunJavascriptMessage")
    except NoHook as exc:
        log.warning("the 3D view draws every frame: this viser cannot run a script (%s)", exc)
        return False
    interface.queue_message(run_script(source=frame_cap_source(software_fps)))
    return True

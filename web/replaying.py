"""The loop's side of the job list: the rows it shows, and a done job's run drawn in the live
panels while a person replays it (web/job_replay.py converts it, web/job_panel.py lists it).

A base class of `web.drawing.Drawing`: the Delta31, footfall and ramp-path panels ask
`_draw_replay` first, and draw the live walk in the panels a replay does not fill.
"""

from __future__ import annotations

from collections.abc import Hashable

import viser

from web.dispatch import Dispatch
from web.job_replay import replay_panel


class Replaying(Dispatch):
    """The job list's rows and the replayed panels, drawn by the loop thread."""

    _jobs_shown: Hashable = None  # the list's version and the replay last shown
    _replay_shown: Hashable = None  # the replay and footfall window last drawn

    def _show_jobs(self) -> None:
        """The job list's rows, sent when a job changed or a replay began or ended."""
        replay = self.replaying
        key = (self.jobs.version, None if replay is None else replay.job_id)
        if key != self._jobs_shown:
            self._jobs_shown = key
            self.panels.job_rows.show(self.jobs.views, key[1])

    def replayed(self, handle: object) -> bool:
        """Whether a replayed job's run fills panel `handle` (the live walk then waits)."""
        replay = self.replaying
        if replay is None:
            return False
        return any(self._handle(p) is handle for p in replay.panels)

    def _handle(self, panel: str) -> viser.GuiHtmlHandle:
        """The live panel a replay's `panel` (job_replay.PANELS) is drawn in."""
        p = self.panels
        return {"d31": p.d31, "footfall": p.footfall, "ramp": p.ramp_plot}[panel]

    def _draw_replay(self) -> tuple[str, ...]:
        """Draw the replayed job's run in the panels it fills (each only when it or the
        footfall window changed); the names of those panels, () while none is replayed."""
        replay = self.replaying
        if replay is None:
            self._replay_shown = None
            return ()
        window = self.footfall_window_s
        if self._replay_shown != (replay.job_id, window):
            self._replay_shown = (replay.job_id, window)
            for panel in replay.panels:
                self.panels.show_html(self._handle(panel), replay_panel(replay, panel, window))
        return replay.panels

"""The job list in the panel: a row per job this viewer submitted or opened (newest first),
with a cancel button while it is queued or running and a replay button once a run or a
hysteresis job is done, and one button back to the live walk while a replay is shown.

viser has no list widget: each row is an HTML line and two buttons, made by the loop thread
when a job joins the list (inside the list's folder) and removed when it leaves. The buttons
only queue requests (`CancelJob`, `ReplayJob`, `StopReplay`); the loop applies them
(web/handlers.py). A button's label names the job's short id, so that a person (and a test)
tells the rows apart.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import viser

from web.job_words import job_row_html, jobs_summary
from web.jobs import JobView
from web.panel_labels import LIVE_AGAIN, cancel_label, replay_label
from web.requests import CancelJob, ReplayJob, Request, RequestQueue, StopReplay


@dataclass
class _Row:
    line: viser.GuiHtmlHandle
    cancel: viser.GuiButtonHandle
    replay: viser.GuiButtonHandle
    shown: tuple[str, bool, bool, str] = ("", False, False, "")  # what was last sent


class JobRows:
    """The rows of the job list (GUI built on the loop thread, callbacks only queue)."""

    def __init__(
        self, gui: viser.GuiApi, folder: viser.GuiFolderHandle, requests: RequestQueue
    ) -> None:
        self._gui = gui
        self._folder = folder
        self._requests = requests
        with folder:
            self.summary = gui.add_html(jobs_summary(()), order=-1e9)
            self.live_again = gui.add_button(LIVE_AGAIN, visible=False, order=-1e9 + 1)
        self.live_again.on_click(self._queue(StopReplay))
        self._rows: dict[int, _Row] = {}
        self._last_summary = ""

    def _queue(self, make: Callable[[], Request]) -> Callable[[viser.GuiEvent], None]:
        def callback(event: viser.GuiEvent) -> None:
            if event.client is not None:
                self._requests.put(make())

        return callback

    def _row(self, key: int) -> _Row:
        """Job `key`'s row, made once: newer jobs sort above older ones."""
        row = self._rows.get(key)
        if row is None:
            base = -10.0 * key
            with self._folder:
                line = self._gui.add_html("", order=base)
                cancel = self._gui.add_button(cancel_label(""), visible=False, order=base + 1)
                replay = self._gui.add_button(replay_label(""), visible=False, order=base + 2)
            cancel.on_click(self._queue(lambda: CancelJob(key)))
            replay.on_click(self._queue(lambda: ReplayJob(key)))
            row = self._rows[key] = _Row(line, cancel, replay)
        return row

    def show(self, views: Sequence[JobView], replaying: str | None) -> None:
        """Loop thread: the list as `views` has it (`replaying`: the job id whose run the
        panels show); only what changed is sent."""
        summary = jobs_summary(views)
        if summary != self._last_summary:
            self._last_summary = summary
            self.summary.content = summary
        if self.live_again.visible != (replaying is not None):
            self.live_again.visible = replaying is not None
        for key in set(self._rows) - {v.key for v in views}:
            row = self._rows.pop(key)
            for handle in (row.line, row.cancel, row.replay):
                handle.remove()
        for v in views:
            row = self._row(v.key)
            on = bool(v.id) and v.id == replaying
            html = job_row_html(v, on)
            shown = (html, v.cancellable, v.replay is not None and not on, v.id)
            if shown == row.shown:
                continue
            if shown[3] != row.shown[3]:
                row.cancel.label = cancel_label(v.id)
                row.replay.label = replay_label(v.id)
            row.line.content = html
            row.cancel.visible = shown[1]
            row.replay.visible = shown[2]
            row.shown = shown

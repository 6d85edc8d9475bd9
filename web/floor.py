"""The floor under the insect: a part of the 3D scene (web/scene.py), which moves it with the
walk each frame.

Grid lines on a 20 x 20 cm patch (1 cm cells, every 5th line darker) kept under the insect:
once the body is 3.5 cm from the patch's centre (so at least 6.5 cm of floor shows on every
side, and a walk along a section line does not make it flicker) the patch jumps to the section
nearest the body, a jump its repeating lines hide. viser's infinite grid shades every pixel of
the view (a full-screen pass, 35-45 ms a frame in software WebGL) and its tinted plane more
(the lit plane about 20 ms); lines cost only their own pixels (benchmarks/viewer_rtf.py;
docs/VIEWER.md). `--shadows` keeps viser's infinite grid (1 cm cells, still): its plane is what
catches the shadows.
"""

from __future__ import annotations

import numpy as np
import viser

from web.style import FLOOR_CELL_RGB, FLOOR_SECTION_RGB

FLOOR_HALF_M, FLOOR_CELL_M, FLOOR_SECTION_M = 0.10, 0.01, 0.05
FLOOR_SHIFT_M = 0.035


class Floor:
    """The floor's node under `parent` (the scene's tilted, camera-following frame)."""

    def __init__(self, server: viser.ViserServer, parent: str, *, shadows: bool) -> None:
        self._at: np.ndarray | None = None  # the patch's centre; None: viser's grid stays
        if shadows:
            self._node: viser.SceneNodeHandle = server.scene.add_grid(
                f"{parent}/floor",
                infinite_grid=True,
                cell_size=FLOOR_CELL_M,
                section_size=FLOOR_SECTION_M,
                cell_color=FLOOR_CELL_RGB,
                section_color=FLOOR_SECTION_RGB,
                fade_distance=0.6,
                plane_color=(235, 230, 215),
                plane_opacity=0.6,
                shadow_opacity=0.25,
            )
            return
        points, colours = floor_lines(FLOOR_HALF_M, FLOOR_CELL_M, FLOOR_SECTION_M)
        self._node = server.scene.add_line_segments(
            f"{parent}/floor",
            points=points,
            colors=colours,
            thickness=1.0,
            thickness_units="screen",
        )
        self._at = np.zeros(2)

    def follow(self, body_xyz: np.ndarray) -> None:
        """Loop thread, inside the frame's `server.atomic()`: the patch under the body (a
        message only when it jumps)."""
        if self._at is None:
            return
        at = floor_centre(body_xyz, self._at)
        if at is not self._at:
            self._node.position = (float(at[0]), float(at[1]), 0.0)
            self._at = at


def floor_centre(body_xyz: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Where the floor patch sits: `centre` (the same object) while the body is within
    FLOOR_SHIFT_M of it along x and y, else the section point nearest the body (a jump the
    repeating lines hide)."""
    xy = np.asarray(body_xyz[:2], dtype=float)
    if np.max(np.abs(xy - centre)) <= FLOOR_SHIFT_M:
        return centre
    return np.round(xy / FLOOR_SECTION_M) * FLOOR_SECTION_M


def floor_lines(half: float, cell: float, section: float) -> tuple[np.ndarray, np.ndarray]:
    """Grid lines on the square [-half, half]^2 at z = 0: (N, 2, 3) end points and their
    (N, 2, 3) colours, every `section / cell`-th line (those through multiples of `section`)
    darker."""
    n = round(half / cell)
    k = np.arange(-n, n + 1)
    along_y = np.zeros((k.size, 2, 3))  # line k: x = k cell, from y = -half to y = half
    along_y[:, :, 0] = (k * cell)[:, None]
    along_y[:, :, 1] = (-half, half)
    along_x = along_y[:, :, [1, 0, 2]]
    points = np.concatenate([along_y, along_x]).astype(np.float32)
    major = np.tile(k % round(section / cell) == 0, 2)
    rgb = np.where(major[:, None], FLOOR_SECTION_RGB, FLOOR_CELL_RGB).astype(np.uint8)
    return points, np.repeat(rgb[:, None, :], 2, axis=1)

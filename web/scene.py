"""The 3D scene: hexapod meshes sent once, then body poses streamed per frame.

Each MjModel body becomes one viser frame holding its geoms' meshes (boxes, capsules, spheres,
built with trimesh in the body's frame); a frame update is then 19 small pose messages inside
one `server.atomic()`. We evaluated mjviser (the mjlab viewer's scene, on PyPI) first: with
viser 1.1.1 its scene makes the browser client throw "Cannot read properties of undefined
(reading 'index')" and lose the WebGL context (seen in headless Chromium), so this module maps
the three primitive geom types the hexapod uses by hand.

Slope. The core tilts gravity, not the floor (slope theta uphill along +x). For the eye we do
the opposite: every dynamic node lives under one frame, `/bodies`, rotated by the slope about
+y, so the floor grid and the insect tilt together while the camera's "up" stays the true
vertical. The same frame's pose implements the follow camera: moving the world under a still
camera keeps orbiting and zooming with the user, where moving each browser's camera would fight
their mouse. "follow" translates the world so the body stays at the origin; "follow + turn"
also turns it about the vertical so the body keeps facing +x (the
heading is a one-second circular mean, `Simulation.heading_rad`, so the view does not shake
with each step).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import trimesh
import viser
import viser.transforms as vtf

from sim_core.contract import LEG_NAMES
from web import controls
from web.floor import Floor
from web.style import GROUND_RGB, PAIR_COLOURS, SKY_RGB, rgb

# Every dynamic node lives under this node; we own its pose (see the module docstring).
BODIES_NODE = "/bodies"
# Insect scale: the body is 4.2 cm long, a tibia 0.3 mm thick. The camera looks down from
# behind and above the right side (elevation ~45 deg), so the left legs show past the body; the
# old side view (-45, -75, 45) mm hid them behind it.
CAMERA_POSITION = (-0.06, -0.05, 0.075)
# Legs are drawn this many times thicker than their (inertia) radii: at 0.15-0.3 mm against an
# 8-12 mm leg, true-to-scale links read as hairlines on screen. Drawing only; physics untouched.
LEG_DRAW_SCALE = 3.0
CAMERA_NEAR, CAMERA_FAR = 5e-4, 20.0
# No environment map: image-based lighting is a texture lookup per lit pixel (~8 ms a frame in
# software WebGL); a hemisphere light fills in instead (its colours: web/style.py). The floor
# under the insect is web/floor.py's part.
# viser's default orbit limits (1 cm .. 10 km) would not let one zoom onto a 2 mm femur
MIN_ORBIT, MAX_ORBIT = 2e-3, 5.0


def slope_rotation(slope_deg: float) -> vtf.SO3:
    """Rotation about +y that lifts +x by `slope_deg` (uphill positive)."""
    return vtf.SO3.from_y_radians(-math.radians(slope_deg))


def world_pose(
    slope_deg: float, mode: str, body_xy: np.ndarray, heading_rad: float | None
) -> tuple[np.ndarray, np.ndarray]:
    """(wxyz, position) of the `/bodies` frame: the slope tilt and the follow camera.

    display = R (x - p) with R = tilt(slope) * turn(-heading) and p the body's floor position;
    "fixed" leaves p = 0 and no turn, "follow" no turn.
    """
    r = slope_rotation(slope_deg)
    if mode == controls.CAMERA_FIXED:
        return r.wxyz, np.zeros(3)
    if mode == controls.CAMERA_HEADING and heading_rad is not None:
        r = r @ vtf.SO3.from_z_radians(-heading_rad)
    p = np.array([float(body_xy[0]), float(body_xy[1]), 0.0])
    return r.wxyz, -r.apply(p)


def foot_geom_ids(model: mujoco.MjModel) -> np.ndarray:
    """Geom ids of the six feet in paper order, found by the core's names `<leg>_foot`."""
    ids = []
    for leg in LEG_NAMES:
        gid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"{leg}_foot")
        if gid < 0:
            raise ValueError(f"model has no geom named {leg}_foot; cannot mark stance")
        ids.append(gid)
    return np.array(ids)


def torso_body_id(model: mujoco.MjModel) -> int:
    """The free-floating body the camera follows: the first child of the world."""
    for b in range(1, model.nbody):
        if model.body_parentid[b] == 0:
            return b
    raise ValueError("model has no body under the world")


class HexapodScene:
    """Owns every 3D node (the floor is its part). Call `update` from the loop thread only."""

    def __init__(
        self, server: viser.ViserServer, model: mujoco.MjModel, *, shadows: bool = False
    ) -> None:
        self.server = server
        # Shadows are extra render passes of every frame; a browser rendering WebGL in software
        # (no GPU) pays them on the CPU the simulation needs. Off unless asked.
        server.scene.configure_default_lights(enabled=True, cast_shadow=shadows)
        server.scene.configure_environment_map(hdri=None)
        server.scene.add_light_hemisphere("/fill", sky_color=SKY_RGB, ground_color=GROUND_RGB)
        self._feet = foot_geom_ids(model)
        self._torso = torso_body_id(model)
        self._frame = server.scene.add_frame(BODIES_NODE, show_axes=False)
        self._bodies = add_body_meshes(server, model, BODIES_NODE)
        self._floor = Floor(server, BODIES_NODE, shadows=shadows)
        r = float(model.geom_size[self._feet[0], 0]) * 2.2
        self._markers = [
            server.scene.add_icosphere(
                f"{BODIES_NODE}/stance/{leg}",
                radius=r,
                color=rgb(PAIR_COLOURS[i // 2]),
                visible=False,
            )
            for i, leg in enumerate(LEG_NAMES)
        ]
        self._stance = np.zeros(6, dtype=bool)
        server.initial_camera.position = CAMERA_POSITION
        server.initial_camera.look_at = (0.0, 0.0, 0.0)
        server.initial_camera.near = CAMERA_NEAR
        server.initial_camera.far = CAMERA_FAR

        @server.on_client_connect
        def _(client: viser.ClientHandle) -> None:
            client.camera.near = CAMERA_NEAR
            client.camera.far = CAMERA_FAR
            client.camera.min_orbit_distance = MIN_ORBIT
            client.camera.max_orbit_distance = MAX_ORBIT

    def update(
        self,
        data: mujoco.MjData,
        stance: np.ndarray,
        *,
        slope_deg: float,
        heading_rad: float | None,
        follow: str,
    ) -> None:
        """Stream one frame of the walk `data` (with its kinematics) and `stance` (6,): body
        poses, stance markers, slope tilt and the camera mode `follow` (controls.CAMERA_MODES);
        it only reads them, the loop steps."""
        stance = np.asarray(stance, dtype=bool)
        wxyz, position = world_pose(slope_deg, follow, data.xpos[self._torso], heading_rad)
        with self.server.atomic():
            if not np.array_equal(self._frame.wxyz, wxyz):
                self._frame.wxyz = wxyz
            if not np.array_equal(self._frame.position, position):
                self._frame.position = position
            self._floor.follow(data.xpos[self._torso])
            for b, handle in self._bodies.items():
                handle.position = data.xpos[b]
                handle.wxyz = data.xquat[b]
            for i, marker in enumerate(self._markers):
                if stance[i]:
                    marker.position = data.geom_xpos[self._feet[i]]
                if stance[i] != self._stance[i]:
                    marker.visible = bool(stance[i])
            self._stance = stance.copy()


def geom_mesh(model: mujoco.MjModel, g: int) -> trimesh.Trimesh | None:
    """A trimesh of geom g in its own frame; None for types the hexapod does not draw."""
    size = model.geom_size[g]
    kind = model.geom_type[g]
    if kind == mujoco.mjtGeom.mjGEOM_BOX:
        return trimesh.creation.box(extents=2.0 * size)
    if kind == mujoco.mjtGeom.mjGEOM_CAPSULE:  # along local z, half-length size[1]; a leg link
        radius = size[0] * LEG_DRAW_SCALE
        return trimesh.creation.capsule(height=2.0 * size[1], radius=radius, count=[12, 12])
    if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
        return trimesh.creation.icosphere(subdivisions=2, radius=size[0])
    return None  # the floor plane: drawn as a grid instead


def add_body_meshes(
    server: viser.ViserServer, model: mujoco.MjModel, root: str
) -> dict[int, viser.FrameHandle]:
    """One frame per moving body, its geoms as child meshes; returns body id -> frame."""
    frames: dict[int, viser.FrameHandle] = {}
    for b in range(1, model.nbody):
        frame = server.scene.add_frame(f"{root}/body{b}", show_axes=False)
        for g in np.flatnonzero(model.geom_bodyid == b):
            mesh = geom_mesh(model, int(g))
            if mesh is None:
                continue
            rgba = model.geom_rgba[g]
            server.scene.add_mesh_simple(
                f"{root}/body{b}/geom{g}",
                vertices=np.asarray(mesh.vertices, dtype=np.float32),
                faces=np.asarray(mesh.faces, dtype=np.uint32),
                color=(int(255 * rgba[0]), int(255 * rgba[1]), int(255 * rgba[2])),
                position=model.geom_pos[g],
                wxyz=model.geom_quat[g],
            )
        frames[b] = frame
    return frames

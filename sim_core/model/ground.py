"""The paper's ground: a viscoelastic spring-damper at each foot, as a compiled MuJoCo callback.

Fujiki et al. model the feet on the ground as viscoelastic elements "with large stiffness and
damping so that the leg tips rarely slipped". With `ModelParams.ground = "penalty"` the feet
leave MuJoCo's constraint contact (their geoms collide with nothing) and this module adds, at
every physics evaluation, for each foot whose sphere dips below the floor (world z = 0; the
core tilts gravity, not the floor):

    normal      F_n = max(0, k_n depth - c_n v_z)                  (never pulls)
    tangential  F_t = -k_t (p_xy - anchor_xy) - c_t v_xy            (anchored at touchdown)
                |F_t| <= mu F_n: beyond it the anchor slides (Coulomb), so slip is measurable

applied at the foot's centre through `mj_applyFT` into `qfrc_passive`. The anchor is set where
the foot touched down and released when it lifts off.

How it is compiled and where its state lives:
- MuJoCo calls `mjcb_passive` at the end of its passive-force stage; `mujoco.batch` requires a
  C function there (a Python callable makes its calls raise). The callback is a numba `cfunc`,
  installed through its ctypes pointer: no Python and no GIL per step, safe on the batch's
  threads because it touches only the (model, data) it is given.
- Its parameters travel in the model as a custom numeric field ("penalty_ground", with a magic
  first value), so every per-simulation model copy of a batch carries them and a model without
  that field (the constraint ground, any other model) is left alone.
- The anchors and touch flags live in `mjData.userdata`, which is part of a simulation's
  integration state (mjSTATE_USERDATA): `mujoco.batch` saves and restores it with each
  simulation's row, so simulations sharing one MjData per thread keep their own anchors.
- The C structs are read through byte offsets of a few pointer fields (`numeric_data`,
  `userdata`, `qfrc_passive`, `site_xpos`) and one size (`nnumeric`), found once by matching
  known values in a probe model's and data's memory, so nothing depends on a header.

Under RK4 the callback runs at each of the four stages and may move the anchor mid-step; the
anchor is a slow variable (it moves only when the foot lands or slides), so this is an explicit
update of a quasi-static state.
"""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path
from typing import Any, cast, no_type_check

import mujoco
import numpy as np
from numba import carray, cfunc, types
from numba.extending import intrinsic

NUMERIC_NAME = "penalty_ground"
MAGIC = 1.23456789e7  # first value of the numeric field: "this model asks for the penalty ground"
N_FEET = 6
# numeric field layout: magic, k_n, c_n, k_t, c_t, mu, radius, site ids (6), body ids (6)
N_PARAMS = 7 + 2 * N_FEET
# userdata layout: per foot (anchor x, anchor y, touching), then scratch for mj calls
UD_STATE = 3 * N_FEET
UD_VEL = UD_STATE  # 6: object velocity (rot, lin)
UD_FORCE = UD_VEL + 6  # 3
UD_TORQUE = UD_FORCE + 3  # 3 (zeros)
UD_POINT = UD_TORQUE + 3  # 3
N_USERDATA = UD_POINT + 3


def ground_numeric(
    *,
    stiffness: float,
    damping: float,
    tangential_stiffness: float,
    tangential_damping: float,
    friction: float,
    foot_radius: float,
    site_ids: list[int],
    body_ids: list[int],
) -> list[float]:
    """The numeric field's values (SI: N/m, N s/m, radius m; ids as floats)."""
    return [MAGIC, stiffness, damping, tangential_stiffness, tangential_damping, friction,
            foot_radius, *map(float, site_ids), *map(float, body_ids)]  # fmt: skip


# --- raw memory access from compiled code -------------------------------------------------------


@intrinsic
def _as_int(typingctx: Any, ptr: Any) -> Any:
    sig = types.int64(types.voidptr)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.ptrtoint(args[0], context.get_value_type(types.int64))

    return sig, codegen


def _from_int(target: Any) -> Any:
    """A compiled cast of an address (int64) to the pointer type `target`."""

    @intrinsic
    def cast(typingctx: Any, addr: Any) -> Any:
        def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
            return builder.inttoptr(args[0], context.get_value_type(target))

        return target(types.int64), codegen

    return cast


_f64_ptr = _from_int(types.CPointer(types.float64))
_i64_ptr = _from_int(types.CPointer(types.int64))
_void_ptr = _from_int(types.voidptr)


def _candidates(base: int, size: int, value: int) -> set[int]:
    """The 8-byte-aligned offsets in [base, base + size) that hold `value`."""
    raw = np.frombuffer(ctypes.string_at(base, size), dtype=np.int64)
    return {int(k) * 8 for k in np.flatnonzero(raw == value)}


def _probe(
    nsite: int, nnumeric: int, nuserdata: int, sensor: bool
) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="b")
    body.add_freejoint()
    body.add_geom(size=[0.1, 0, 0])
    for k in range(nsite):
        body.add_site(name=f"s{k}")
    for k in range(nnumeric):
        spec.add_numeric(name=f"n{k}", data=[float(k), 0.0])
    spec.nuserdata = nuserdata
    if sensor:  # zero-size neighbours (act_dot, sensordata) share userdata's address
        spec.add_sensor(type=mujoco.mjtSensor.mjSENS_FRAMEPOS, objtype=mujoco.mjtObj.mjOBJ_SITE,
                        objname="s0")  # fmt: skip
        arm = body.add_body(name="arm")
        arm.add_joint(name="hinge", type=mujoco.mjtJoint.mjJNT_HINGE)
        arm.add_geom(size=[0.05, 0, 0])
        act = spec.add_actuator(name="a", target="hinge")
        act.trntype = mujoco.mjtTrn.mjTRN_JOINT
        act.dyntype = mujoco.mjtDyn.mjDYN_INTEGRATOR
    m = spec.compile()
    return m, mujoco.MjData(m)


@functools.cache
def struct_offsets() -> tuple[int, int, int, int, int]:
    """Byte offsets of (mjModel.nnumeric, mjModel.numeric_data, mjData.userdata,
    mjData.qfrc_passive, mjData.site_xpos): the offsets that hold the known value in two
    probes of different sizes (a zero-size array can share an address with its neighbour in
    one probe, not in both). mjModel is ~9 kB of sizes and pointers; mjData keeps ~157 kB of
    solver statistics before its pointers (userdata sits at 160 800 bytes in MuJoCo 4.0)."""
    found: list[set[int]] = []
    for nsite, nnum, nud, sensor in ((3, 62, 4, False), (5, 71, 9, True)):
        m, d = _probe(nsite, nnum, nud, sensor)
        row = [
            _candidates(m._address, 1 << 11, m.nnumeric),
            _candidates(m._address, 1 << 15, m.numeric_data.ctypes.data),
            *(_candidates(d._address, 1 << 18, a.ctypes.data)
              for a in (d.userdata, d.qfrc_passive, d.site_xpos)),
        ]  # fmt: skip
        found = row if not found else [a & b for a, b in zip(found, row, strict=True)]
    if any(len(c) != 1 for c in found):
        raise RuntimeError(f"cannot locate MuJoCo's struct fields: {found}")
    nnum, numeric, userdata, passive, site_xpos = (c.pop() for c in found)
    return nnum, numeric, userdata, passive, site_xpos


def _library() -> ctypes.CDLL:
    path = next(Path(mujoco.__file__).parent.glob("libmujoco.so*"))
    return ctypes.CDLL(str(path))


@functools.cache
def install() -> int:
    """Compile the callback and install it as mjcb_passive (once per process); its address."""
    lib = _library()
    apply_ft = lib.mj_applyFT
    apply_ft.argtypes = [ctypes.c_void_p] * 5 + [ctypes.c_int, ctypes.c_void_p]
    apply_ft.restype = None
    obj_vel = lib.mj_objectVelocity
    obj_vel.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int, ctypes.c_int,
                        ctypes.c_void_p, ctypes.c_int]  # fmt: skip
    obj_vel.restype = None
    off_nnum, off_num, off_ud, off_passive, off_site = struct_offsets()
    site_obj = int(mujoco.mjtObj.mjOBJ_SITE)

    @cfunc(types.void(types.voidptr, types.voidptr))
    @no_type_check  # numba's intrinsics and carray are beyond a type checker
    def passive(m: Any, d: Any) -> None:  # pragma: no cover (compiled)
        ma = _as_int(m)
        da = _as_int(d)
        if carray(_i64_ptr(ma + off_nnum), 1)[0] <= 0:
            return
        num = carray(_f64_ptr(carray(_i64_ptr(ma + off_num), 1)[0]), N_PARAMS)
        if num[0] != MAGIC:
            return
        k_n, c_n, k_t, c_t, mu, radius = num[1], num[2], num[3], num[4], num[5], num[6]
        ud_addr = carray(_i64_ptr(da + off_ud), 1)[0]
        ud = carray(_f64_ptr(ud_addr), N_USERDATA)
        sites_addr = carray(_i64_ptr(da + off_site), 1)[0]
        qfrc = _void_ptr(carray(_i64_ptr(da + off_passive), 1)[0])
        for foot in range(N_FEET):
            sid = int(num[7 + foot])
            bid = int(num[7 + N_FEET + foot])
            pos = carray(_f64_ptr(sites_addr + 24 * sid), 3)
            depth = radius - pos[2]
            s = 3 * foot
            if depth <= 0.0:
                ud[s + 2] = 0.0  # lifted off: release the anchor
                continue
            obj_vel(m, d, site_obj, sid, _void_ptr(ud_addr + 8 * UD_VEL), 0)
            vx, vy, vz = ud[UD_VEL + 3], ud[UD_VEL + 4], ud[UD_VEL + 5]
            fn = k_n * depth - c_n * vz
            if fn < 0.0:
                fn = 0.0
            if ud[s + 2] == 0.0:  # touchdown: anchor here
                ud[s], ud[s + 1], ud[s + 2] = pos[0], pos[1], 1.0
            fx = -k_t * (pos[0] - ud[s]) - c_t * vx
            fy = -k_t * (pos[1] - ud[s + 1]) - c_t * vy
            ft = (fx * fx + fy * fy) ** 0.5
            cap = mu * fn
            if ft > cap:  # sliding: cap the force, move the anchor to match the spring
                scale = cap / ft
                fx *= scale
                fy *= scale
                ud[s] = pos[0] + (fx + c_t * vx) / k_t
                ud[s + 1] = pos[1] + (fy + c_t * vy) / k_t
            ud[UD_FORCE], ud[UD_FORCE + 1], ud[UD_FORCE + 2] = fx, fy, fn
            ud[UD_TORQUE], ud[UD_TORQUE + 1], ud[UD_TORQUE + 2] = 0.0, 0.0, 0.0
            ud[UD_POINT], ud[UD_POINT + 1], ud[UD_POINT + 2] = pos[0], pos[1], pos[2]
            apply_ft(m, d, _void_ptr(ud_addr + 8 * UD_FORCE), _void_ptr(ud_addr + 8 * UD_TORQUE),
                     _void_ptr(ud_addr + 8 * UD_POINT), bid, qfrc)  # fmt: skip

    install.callback = passive  # type: ignore[attr-defined]  # keep it alive
    mujoco.set_mjcb_passive(passive.ctypes)
    return int(cast(int, passive.address))

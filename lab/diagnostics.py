"""Mechanism diagnostics of the full model: what the body does on its legs, measured.

Three numbers the gait-selection argument (shared/notes/gait-mechanism.md) rests on:

- `body_modes`: heave, pitch and roll of the body standing on six feet (the PD legs and the
  ground as its springs), from a ring-down after a velocity kick: frequency and damping ratio,
  to set against the stride period (89-113 ms);
- `support_stiffness`: the vertical stiffness each leg pair gives the body at its hips, from a
  small static push at the centre of mass; their ratio r = k_middle / mean(k_fore, k_hind)
  decides (quasi-statically) whether a fore-leg landing lifts (r < 2) or lowers (r > 2) the hind
  hip;
- `load_share`: the vertical load each pair carries and the mean pitch while walking with
  Delta31 held (phase resetting off) at two speeds, i.e. whether a speed-dependent fore/hind
  load shift exists.

They use MuJoCo directly on the simulated model (`build_model(visual=False)`); nothing here
changes the model.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import mujoco
import numpy as np

from sim_core import ModelParams, RunSpec
from sim_core.contract import LEG_NAMES
from sim_core.research import (
    BatchRunner,
    attachment_points,
    build_model,
    leg_qpos_addresses,
    mid_stance_angles,
)

PAIRS = ("fore", "middle", "hind")
# each leg's pair (0 fore, 1 middle, 2 hind), read from its name (R1 L1 R2 L2 R3 L3)
LEG_PAIR = np.array([int(name[1:]) - 1 for name in LEG_NAMES])


@dataclass(frozen=True)
class Mode:
    """One body mode from a ring-down: frequency (Hz) and damping ratio (1 or more: overdamped,
    then `decay_ms` is the e-folding time of the return)."""

    name: str
    frequency_hz: float | None
    damping_ratio: float | None
    decay_ms: float | None


def _standing(p: ModelParams) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The hexapod on six feet at mid-stance, PD set-points holding that pose, settled 0.3 s."""
    model = build_model(p, visual=False)
    data = mujoco.MjData(model)
    q = mid_stance_angles(p).ravel()
    data.qpos[leg_qpos_addresses(model)] = q
    data.qpos[2] = p.trajectory.stand_height - p.legs.attach_z + p.legs.foot_radius
    data.qpos[3] = 1.0
    data.act[:] = q  # set-points; ctrl = 0 keeps them (integrator dynamics)
    data.ctrl[:] = 0.0
    for _ in range(round(0.3 / model.opt.timestep)):
        mujoco.mj_step(model, data)
    return model, data


def _pitch_roll(quat: np.ndarray) -> tuple[float, float]:
    w, x, y, z = quat
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    return pitch, roll


def _fit_ring(t: np.ndarray, x: np.ndarray, name: str) -> Mode:
    """Frequency from zero crossings, damping from the log decrement of successive peaks; an
    overdamped return gives the e-folding time instead."""
    x = x - x[-len(x) // 5 :].mean()  # the settled value from the last fifth
    peaks = [i for i in range(1, len(x) - 1) if abs(x[i]) >= abs(x[i - 1]) and abs(x[i]) > abs(
        x[i + 1]) and abs(x[i]) > 0.02 * np.abs(x).max()]  # fmt: skip
    crossings = np.flatnonzero(np.sign(x[1:]) != np.sign(x[:-1]))
    if len(crossings) >= 3 and len(peaks) >= 3:
        period = 2 * float(np.mean(np.diff(t[crossings])))
        amps = np.abs(x[peaks])
        dec = float(np.mean(np.log(amps[:-1] / amps[1:])))  # per half period
        zeta = 2 * dec / math.sqrt(4 * math.pi**2 + (2 * dec) ** 2)
        return Mode(name, 1.0 / period, zeta, None)
    a = np.abs(x)
    k = int(np.argmax(a))
    below = np.flatnonzero(a[k:] < a[k] / math.e)
    decay = float(t[k + below[0]] - t[k]) * 1e3 if below.size else None
    return Mode(name, None, None, decay)


def body_modes(params: ModelParams | None = None, *, window_s: float = 0.06) -> list[Mode]:
    """Heave, pitch and roll ring-downs of the standing body after a small velocity kick."""
    p = params or ModelParams()
    kicks = {"heave": (2, 0.01), "roll": (3, 1.0), "pitch": (4, 1.0)}  # qvel index, m/s | rad/s
    out = []
    for name, (dof, v) in kicks.items():
        model, data = _standing(p)
        data.qvel[dof] += v
        n = round(window_s / model.opt.timestep)
        t = np.arange(n) * model.opt.timestep
        x = np.empty(n)
        for k in range(n):
            mujoco.mj_step(model, data)
            pitch, roll = _pitch_roll(data.qpos[3:7])
            x[k] = data.qpos[2] if name == "heave" else (roll if name == "roll" else pitch)
        out.append(_fit_ring(t, x, name))
    return out


def _foot_forces(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """(6,) normal force on each foot, N (paper leg order)."""
    foot = {model.geom(f"{n}_foot").id: i for i, n in enumerate(LEG_NAMES)}
    out = np.zeros(6)
    f = np.zeros(6)
    for c in range(data.ncon):
        con = data.contact[c]
        leg = foot.get(con.geom1, foot.get(con.geom2))
        if leg is not None:
            mujoco.mj_contactForce(model, data, c, f)
            out[leg] += f[0]
    return out


def _hip_heights(p: ModelParams, data: mujoco.MjData) -> np.ndarray:
    """(6,) world height of each coxa attachment."""
    torso = 1
    return np.asarray(
        data.xpos[torso][2] + (data.xmat[torso].reshape(3, 3) @ attachment_points(p).T)[2]
    )


def support_stiffness(
    params: ModelParams | None = None, *, push_share: float = 0.1
) -> dict[str, Any]:
    """Per-pair vertical stiffness at the hips under a static push at the centre of mass
    (`push_share` of the body's weight), and r = k_middle / mean(k_fore, k_hind)."""
    p = params or ModelParams()
    model, data = _standing(p)
    f0, z0 = _foot_forces(model, data), _hip_heights(p, data)
    torso = 1
    data.xfrc_applied[torso, 2] = -push_share * p.body.body_mass * 9.81
    for _ in range(round(0.3 / model.opt.timestep)):
        mujoco.mj_step(model, data)
    df, dz = _foot_forces(model, data) - f0, _hip_heights(p, data) - z0
    k = {}
    for pair, name in enumerate(PAIRS):
        legs = LEG_PAIR == pair
        k[name] = float(df[legs].sum() / -dz[legs].mean())  # N/m per pair
    r = k["middle"] / (0.5 * (k["fore"] + k["hind"]))
    return {"k_pair_N_per_m": k, "ratio_r": r, "load_at_rest_N": f0.tolist()}


def load_share(
    params: ModelParams | None = None,
    *,
    betas: Sequence[float] = (0.62, 0.70),
    d31: float = 2.2,
    duration_s: float = 2.0,
    settle_s: float = 0.7,
) -> dict[float, dict[str, Any]]:
    """Per-pair share of the stance feet's ground penetration (a load proxy: MuJoCo's soft
    contact presses a foot in monotonically with its load) and the mean body pitch, walking
    with Delta31 held (resets off) at each beta."""
    specs = [RunSpec(beta=b, d31_init=d31, duration_s=duration_s, phase_reset=False)
             for b in betas]  # fmt: skip
    runner = BatchRunner(specs, params, nthread=1)
    p = runner.params
    depth = np.zeros((len(specs), 6))

    def press(r: BatchRunner) -> None:
        if r.time >= settle_s:
            h = r.feet[: len(specs), :, :6, 2] - p.legs.foot_radius  # (n, k, 6) clearance
            depth[:] += np.clip(-h, 0.0, None).sum(axis=1)

    runner.run(hook=press)
    out = {}
    for i, beta in enumerate(betas):
        res = runner.result(i)
        share = np.array([depth[i, LEG_PAIR == k].sum() for k in range(3)])
        share = share / share.sum()
        late = res.series.times_s > settle_s
        pitch = [_pitch_roll(q)[0] for q in res.series.body_quat[late]]
        out[float(beta)] = {
            "share": dict(zip(PAIRS, share.round(4).tolist(), strict=True)),
            "mean_pitch_mrad": float(np.mean(pitch) * 1e3),  # + nose down (MuJoCo's y axis)
            "error": res.error,
        }
    return out


def diagnose(params: ModelParams | None = None) -> dict[str, Any]:
    """All three, JSON-able."""
    return {
        "body_modes": [asdict(m) for m in body_modes(params)],
        "support": support_stiffness(params),
        "load_share": load_share(params),
    }

"""The drift surface: the pin (an instrument in the oscillator step), the probes' reading, the
zeros and folds drawn from them, and the check against the finder."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from sim_core import RunSpec, simulate
from sim_core.contract import FinderOutput, pin_problem
from sim_core.contract.surface import SurfaceConfig, SurfacePoint, SurfaceZero, grid
from sim_core.model.cpg import advance_phases, coupling, pin
from sim_core.model.gait import TWO_PI
from sim_core.model.params import phi_aep
from sim_core.paper.surface import (
    Probe,
    assemble,
    branches_of,
    drift_surface,
    read_probe,
    zeros_of,
)
from sim_core.paper.surface_check import STABLE_TOL, check_beta
from sim_core.runs.cache import ResultCache

REPO = Path(__file__).resolve().parents[2]
KC, KI = 32.0, 40.0


# --- the pin ------------------------------------------------------------------------------------
def test_the_pin_is_refused_where_it_makes_no_sense() -> None:
    with pytest.raises(ValidationError) as exc:
        RunSpec(pin_d31=2.0, phase_reset=False)
    assert pin_problem(2.0, False) in str(exc.value)
    for bad in (-0.1, TWO_PI, 7.0):
        with pytest.raises(ValidationError, match="pin_d31"):
            RunSpec(pin_d31=bad)
    with pytest.raises(ValidationError, match="pin_gain_per_s"):
        RunSpec(pin_d31=2.0, pin_gain_per_s=0.0)
    assert pin_problem(None, False) is None and pin_problem(2.0, True) is None


def test_without_a_pin_the_step_is_eq_1_alone_bit_for_bit() -> None:
    """pin_gain 0 runs exactly the midpoint step of eq. 1 (the operations before the pin)."""
    rng = np.random.default_rng(3)
    h, omega = 5e-4, 110.0
    for _ in range(20):
        phi = rng.uniform(0, TWO_PI, 6)
        out, scratch = np.empty(6), np.empty((2, 6))
        advance_phases(phi, omega, KC, KI, 2.0, 0.0, h, out, scratch)
        g, mid = np.empty(6), np.empty(6)
        coupling(phi, KC, KI, g)
        for i in range(6):
            mid[i] = phi[i] + 0.5 * h * (omega + g[i])
        coupling(mid, KC, KI, g)
        want = np.array([phi[i] + h * (omega + g[i]) for i in range(6)])
        assert np.array_equal(out, want)


def test_the_pin_term_is_its_equation() -> None:
    """fore i, middle i + 2: K sin(phi_m - phi_i - D); hind h, middle h - 2:
    K sin(phi_m + D - phi_h); the middle legs untouched."""
    rng = np.random.default_rng(5)
    phi = rng.uniform(0, TWO_PI, 6)
    d, k = 2.1, 30.0
    g = np.zeros(6)
    pin(phi, d, k, g)
    want = np.zeros(6)
    for i in (0, 1):
        want[i] = k * math.sin(phi[i + 2] - phi[i] - d)
    for h in (4, 5):
        want[h] = k * math.sin(phi[h - 2] + d - phi[h])
    assert np.allclose(g, want, rtol=0, atol=1e-12)


def test_a_pinned_walk_stays_where_a_free_one_drifts() -> None:
    """At beta 0.66 a free walk from 2.4 drifts several mrad per cycle (the metachronal side
    attracts); held at 2.4 it stays within a few hundredths."""
    free = simulate(RunSpec(beta=0.66, d31_init=2.4, duration_s=3.0))
    held = simulate(RunSpec(beta=0.66, d31_init=2.4, pin_d31=2.4, duration_s=3.0))
    late = held.events.d31[held.events.d31_times_s > 1.0]
    assert late.size > 10 and np.all(np.abs(late - 2.4) < 0.05)
    assert abs(free.events.d31[-1] - 2.4) > 0.06


# --- reading a probe ----------------------------------------------------------------------------
def _result(beta: float, jumps: list[float], d31: float, spread: float = 0.0) -> dict:
    """A synthetic probe result: each leg lands every 0.1 s with jump e_i (e = phi_AEP - phi)."""
    aep = phi_aep(beta)
    t = np.arange(0.05, 3.0, 0.1)
    tds = [t.tolist() for _ in range(6)]
    phases = [[(aep - e) % TWO_PI] * t.size for e in jumps]
    wobble = spread * np.sin(np.arange(t.size))
    return {
        "touchdowns_s": tds,
        "touchdown_phases": phases,
        "d31": (d31 + wobble).tolist(),
        "d31_times_s": t.tolist(),
        "failure": None,
    }


def test_a_probe_reads_the_drift_of_its_jumps() -> None:
    cfg = SurfaceConfig()
    e = [-0.02, -0.02, 0.01, 0.01, 0.004, 0.004]  # 1/4 [(e5 + e6) - (e1 + e2)] = +0.012
    p = read_probe(Probe(0.64, 2.0, 2.0), _result(0.64, e, 2.01), cfg)
    assert p.usable and p.drift == pytest.approx(0.012, abs=1e-12)
    assert p.drift_se == pytest.approx(0.0, abs=1e-12) and p.d31 == pytest.approx(2.01)
    after_settling = np.arange(0.05, 3.0, 0.1) > cfg.settle_s  # the leg-1 touchdowns it samples
    assert p.cycles == after_settling.sum() and p.jumps[0] == pytest.approx(-0.02)


def test_a_probe_that_wanders_or_leaves_its_pin_is_kept_but_not_used() -> None:
    cfg = SurfaceConfig()
    e = [0.0] * 6
    wander = read_probe(Probe(0.64, 2.0, 2.0), _result(0.64, e, 2.0, spread=0.05), cfg)
    assert not wander.usable and "not periodic" in wander.why
    away = read_probe(Probe(0.64, 1.4, 2.0), _result(0.64, e, 1.7), cfg)
    assert not away.usable and "off its pin" in away.why
    failed = read_probe(Probe(0.64, 2.0, 2.0), {"failure": {"kind": "flipped"}}, cfg)
    assert not failed.usable and failed.drift is None


# --- zeros, bands, branches, folds --------------------------------------------------------------
def _pt(beta: float, x: float, d_mrad: float, se_mrad: float = 0.0) -> SurfacePoint:
    return SurfacePoint(
        beta=beta,
        pin_d31=x,
        d31=x,
        spread=0.0,
        drift=d_mrad * 1e-3,
        drift_se=se_mrad * 1e-3,
        jumps=[0.0] * 6,
        cycles=20,
        usable=True,
    )


def test_zeros_are_resolved_only_between_clear_neighbours() -> None:
    cfg = SurfaceConfig()
    curve = [
        (1.70, 4.0),
        (1.75, -2.0),
        (1.80, 0.1),
        (1.85, 0.05),
        (1.90, 3.0),
        (1.95, 2.0),
        (2.00, 0.1),
        (2.05, 1.5),
        (2.10, -2.0),
    ]
    zeros, near = zeros_of([_pt(0.64, x, d) for x, d in curve], cfg)
    z = {round(z.d31, 3): z for z in zeros}
    s1 = z[round(1.70 + 0.05 * 4 / 6, 3)]  # + to - between neighbours: resolved, stable
    assert s1.stable and s1.resolved and s1.slope == pytest.approx(-0.12)
    # - to + across two in-floor probes (1.75 .. 1.90, wider than 0.05): unresolved, unstable
    u = [z for z in zeros if not z.stable]
    assert len(u) == 1 and not u[0].resolved and (u[0].lo, u[0].hi) == (1.75, 1.90)
    # + back to + across an in-floor probe: a near-zero band, not a zero
    assert [(n.lo, n.hi, n.sign) for n in near] == [(1.95, 2.05, 1)]
    assert sum(z.stable for z in zeros) == 2


def test_the_noise_floor_follows_the_standard_error() -> None:
    cfg = SurfaceConfig()
    pts = [_pt(0.64, 1.70, 2.0), _pt(0.64, 1.75, -1.0, se_mrad=0.5), _pt(0.64, 1.80, -3.0)]
    zeros, _ = zeros_of(pts, cfg)
    assert len(zeros) == 1 and zeros[0].lo == 1.70 and zeros[0].hi == 1.80
    assert not zeros[0].resolved  # 1.0 mrad < 3 x 0.5: the middle probe is inside the floor


def test_branches_link_stable_zeros_and_folds_mark_their_ends() -> None:
    cfg = SurfaceConfig()

    def zero(b: float, x: float) -> SurfaceZero:
        return SurfaceZero(
            beta=b, d31=x, lo=x - 0.02, hi=x + 0.02, stable=True, slope=-0.1, resolved=True
        )

    betas = [0.62, 0.63, 0.64, 0.65]
    zs = [
        zero(0.62, 1.76),
        zero(0.63, 1.75),
        zero(0.64, 1.74),
        zero(0.65, 1.74),
        zero(0.62, 2.95),
        zero(0.63, 2.94),
        zero(0.64, 2.30),
    ]
    branches, folds = branches_of(zs, betas, cfg)
    assert sorted(len(b.betas) for b in branches) == [1, 2, 4]
    ends = {(f.beta_lo, f.beta_hi, f.side) for f in folds}
    assert (0.63, 0.64, "ends as beta rises") in ends  # the 2.95 branch
    assert (0.63, 0.64, "ends as beta falls") in ends  # the 2.30 branch begins at 0.64
    assert (0.64, 0.65, "ends as beta rises") in ends


# --- against the finder -------------------------------------------------------------------------
def _finder_cell(beta: float):  # the committed finder output (docs/figures/bifurcation.json)
    out = FinderOutput.model_validate_json((REPO / "docs/figures/bifurcation.json").read_text())
    return next(c for c in out.cells if abs(c.beta - beta) < 1e-9)


def test_the_check_fails_a_surface_that_misses_a_finder_state() -> None:
    cfg = SurfaceConfig()
    cell = _finder_cell(0.70)  # one stable state, 1.685
    x = cell.stable()[0].d31
    curve = [(x - 0.07, 5.0), (x - 0.02, 2.0), (x + 0.02, -2.0), (x + 0.07, -5.0)]
    good = assemble([0.70], [_pt(0.70, a, d) for a, d in curve], cfg, sim_s=0.0)
    assert check_beta(good, cell).ok
    shift = 2 * STABLE_TOL
    bad = assemble([0.70], [_pt(0.70, a + shift, d) for a, d in curve], cfg, sim_s=0.0)
    r = check_beta(bad, cell)
    assert not r.ok and len(r.misses) == 2  # our zero has no state, the state has no zero


# --- the whole path -----------------------------------------------------------------------------
def test_drift_surface_runs_through_the_cache_and_resumes(tmp_path: Path) -> None:
    cfg = SurfaceConfig(d31_grid=(1.9, 2.3), settle_s=0.5, average_s=0.5, block_s=0.25)
    seen: list[float] = []
    s = drift_surface(
        [0.655],
        cache=ResultCache(tmp_path),
        config=cfg,
        refine=False,
        progress=False,
        on_progress=seen.append,
    )
    assert len(s.points) == 2 and s.sim_s == pytest.approx(2.0)
    assert all(p.drift is not None for p in s.points) and seen[-1] == pytest.approx(1.0)
    # the metachronal side attracts at 0.655: d falls from 1.9 to 2.3 through a stable zero
    assert s.points[0].drift is not None and s.points[1].drift is not None
    assert s.points[0].drift > 0 > s.points[1].drift
    assert [z.stable for z in s.zeros] == [True]
    again = drift_surface(
        [0.655], cache=ResultCache(tmp_path), config=cfg, refine=False, progress=False
    )
    assert again.model_dump() == s.model_dump()


def test_the_surface_command_prints_zeros_and_refuses_bad_grids(tmp_path: Path) -> None:
    cmd = [
        sys.executable,
        "-m",
        "sim_core.cli",
        "surface",
        "--no-progress",
        "--no-refine",
        "--backend",
        "inline",
        "--cache",
        str(tmp_path),
    ]
    bad = subprocess.run(
        [*cmd, "--beta", "0.64", "--d31", "3:2:0.1"], capture_output=True, text=True, cwd=REPO
    )
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "LO < HI" in bad.stderr
    bad = subprocess.run([*cmd, "--beta", "0.4"], capture_output=True, text=True, cwd=REPO)
    assert bad.returncode == 2 and "beta" in bad.stderr and bad.stderr.count("\n") == 1
    grid_text = "1.9:2.3:0.4"
    assert grid(1.9, 2.3, 0.4) == (1.9, 2.3)
    ok = subprocess.run(
        [*cmd, "--beta", "0.655", "--d31", grid_text, "--json"],
        capture_output=True,
        text=True,
        cwd=REPO,
        check=True,
    )
    surface = json.loads(ok.stdout)
    assert [z["stable"] for z in surface["zeros"]] == [True]


@pytest.mark.slow
def test_surface_check_agrees_with_the_finder_at_five_betas() -> None:
    """Issue 39, point 3: stable zeros within 0.03 rad of the finder's states and borders
    within 0.05, at 0.62, 0.64, 0.655, 0.675 and 0.70 (about 1,300 simulated s)."""
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "sim_core.cli",
            "surface-check",
            "--no-progress",
            "--cache",
            "out/cache",
        ],
        capture_output=True,
        text=True,
        cwd=REPO,
    )
    assert out.returncode == 0, out.stdout + out.stderr

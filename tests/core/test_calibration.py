"""The calibration study's scoring, reachability screen and return-map construction."""

import math

import numpy as np
import pytest

from lab.calibrate import reachable
from lab.objectives import Evaluation
from lab.space import SEARCH_SPACE
from sim_core import ModelParams
from sim_core.contract.returnmap import ReturnMap
from sim_core.model.params import PARAMETER_NAMES
from sim_core.numerics.convergence import ConvergenceRow, convergence_check
from sim_core.paper.protocols import return_map


def _ev(fast: list[float | None], slow: list[float | None], bis: list[float | None]) -> Evaluation:
    return Evaluation(
        params={}, finals={0.62: fast, 0.70: slow, 0.655: bis}, speed_error=0.0, max_slip=0.0,
        diverged=0,
    )  # fmt: skip


def test_score_prefers_the_papers_branches() -> None:
    paper = _ev([2.9] * 8, [1.9] * 8, [2.9, 1.9])
    swapped = _ev([1.9] * 8, [2.9] * 8, [2.9, 1.9])
    monostable = _ev([2.9] * 8, [1.9] * 8, [2.9, 2.9])
    diverged = _ev([None] * 8, [1.9] * 8, [2.9, 1.9])
    assert paper.score() == pytest.approx(0.0)
    assert paper.score() < monostable.score() < swapped.score()
    assert diverged.score() > paper.score() + 8 * 3


def test_search_space_stays_inside_the_models_own_bounds() -> None:
    for name, r in SEARCH_SPACE.items():
        assert name in PARAMETER_NAMES
        assert r.low < r.high and len(r.reason) > 10
        ModelParams.of(**{name: r.low})
        ModelParams.of(**{name: r.high})


def test_reachability_screen() -> None:
    assert reachable(ModelParams())
    assert not reachable(ModelParams.of(stand_height=11.9e-3, foot_y=13e-3))


def test_return_map_pairs_are_lagged_delta31() -> None:
    rm = return_map(None, beta=0.66, inits=[2.0, 3.0], duration_s=0.8, lag=4, skip=1)
    assert rm.x.size == rm.y.size > 0
    assert ((0 <= rm.x) & (rm.x < 2 * math.pi)).all()


def test_drift_per_cycle_bins() -> None:
    x = np.array([1.0, 1.0, 3.0])
    rm = ReturnMap(beta=0.6, lag=4, x=x, y=x + np.array([0.4, 0.8, -0.4]))
    centers, drift = rm.drift_per_cycle(bins=4)
    assert centers.size == 4
    assert drift[0] == pytest.approx(0.15) and drift[1] == pytest.approx(-0.1)
    assert np.isnan(drift[2:]).all()


def test_convergence_rows_and_a_tiny_check() -> None:
    assert ConvergenceRow(0.6, 1.0, 2.0, 2.01, "a", "a").difference == pytest.approx(0.01)
    assert ConvergenceRow(0.6, 1.0, None, 2.0, None, "a").difference == math.inf
    report = convergence_check(betas=(0.66,), inits=(2.5,), duration_s=0.3, dt_s=1e-4)
    assert len(report.rows) == 1 and report.dt_s == 1e-4
    assert "agree" in report.summary()


def test_outcome_gap_counts_disagreements() -> None:
    from lab.objectives import outcome_gap

    a = _ev([2.9, None, 1.0], [1.9], [])
    b = _ev([2.8, 2.0, None], [1.9], [])
    assert outcome_gap(a, b) == pytest.approx(0.1 + 2 * math.pi)


def test_open_loop_drift_shapes_and_a_uniform_hind_bias() -> None:
    from sim_core.model.probes import open_loop_drift

    grid = [2.0, 3.0]
    kw = {"betas": [0.66], "d31s": grid, "duration_s": 0.9, "settle_s": 0.3}
    base, jumps = open_loop_drift(ModelParams(), **kw)
    assert base.shape == (1, 2) and jumps.shape == (1, 2, 6) and np.isfinite(jumps).all()
    # centre of mass moved back loads the hind legs: they land earlier, drift goes up
    back, _ = open_loop_drift(ModelParams.of(com_offset_x=-3e-3), **kw)
    assert (back > base).all()


def test_sensitivity_writes_its_tornado_and_json(tmp_path) -> None:
    import json

    from lab.sensitivity import run_sensitivity

    report = run_sensitivity(tmp_path, names=["kp_yaw"], betas=(0.62,), n_init=2,
                             duration_s=0.5, log=lambda _: None)  # fmt: skip
    assert set(report["sensitivity"]) == {"base", "kp_yaw"}
    assert set(report["sensitivity"]["kp_yaw"]) == {"-", "+"}
    assert len(report["sensitivity"]["base"]["0"][0]["finals"]) == 2
    assert (tmp_path / "sensitivity_tornado.png").stat().st_size > 0
    on_disk = json.loads((tmp_path / "sensitivity.json").read_text())
    assert on_disk["sensitivity"] == json.loads(json.dumps(report["sensitivity"]))


def test_numerics_grid_reports_a_failing_configuration_as_failed() -> None:
    from sim_core.numerics.convergence import grid_study

    points, _ = grid_study(
        integrators=("euler", "implicitfast"), dts=(1e-3, 5e-5), betas=(0.66,), inits=(3.0,),
        duration_s=0.4, with_batch=False, check_reference=False, drift_reference=None,
    )  # fmt: skip
    status = {(p.label, p.dt_s): p for p in points}
    assert ("implicitfast (step touchdown)", 5e-5) in status  # the touchdown-timing series
    bad = status[("euler", 1e-3)]
    # the guard names what it saw first: a MuJoCo warning, non-finite state, a flip or a fall
    # (the 2026-11-25 defaults flip first at this step; the older ones warned)
    assert bad.status == "fails" and bad.error_rad is None
    assert bad.failure.split(" ")[0] in ("unstable", "non-finite", "flip", "fall")
    good = status[("implicitfast", 5e-5)]
    assert good.status != "fails" and good.error_rad is not None and good.wall_per_sim_s > 0
    # the paper's ground is a column of its own, measured against RK4 on the same ground
    penalty = status[("implicitfast (penalty ground)", 5e-5)]
    assert penalty.status == "ok", penalty
    assert ("rk4 (penalty ground)", 5e-5) in status


def test_drift_error_shrinks_with_the_timestep_and_a_failed_probe_is_nan() -> None:
    from sim_core.numerics.convergence import drift_rates

    def probe(dt: float) -> np.ndarray:
        return drift_rates("implicitfast", dt, betas=(0.62,), d31s=(1.9, 2.5))

    ref, coarse, fine = probe(2.5e-5), probe(1e-4), probe(5e-5)
    assert ref.shape == (1, 2) and np.isfinite(ref).all()
    # below the metachronal branch (2.05 at beta 0.62) the map pulls up, above it down
    assert ref[0, 0] > 0 > ref[0, 1]
    # first-order integrator: halving the step shrinks the error (measured ~0.0025 -> 0.0009)
    assert np.abs(coarse - ref).max() > np.abs(fine - ref).max()
    failed = drift_rates("euler", 1e-3, betas=(0.62,), d31s=(1.9,), duration_s=0.6)
    assert np.isnan(failed).all()


def test_drift_score_pushes_toward_the_target_the_short_way() -> None:
    from lab.objectives import DRIFT_GRID, drift_score
    from sim_core.model.gait import angle_diff

    # a grid point just below the target must count a positive drift as a push toward it
    assert float(angle_diff(2.9, 2.7)) > 0 > float(angle_diff(2.9, 3.1))
    assert DRIFT_GRID.size == 18
    score = drift_score(ModelParams(), targets={0.62: 2.9}, duration_s=0.6)
    assert set(score) == {0.62} and -1.0 <= score[0.62] <= 1.0


def test_a_chattering_configuration_is_reported_as_failed_with_its_kind() -> None:
    from sim_core.numerics.convergence import grid_study

    points, info = grid_study(
        integrators=("implicitfast",), dts=(7.5e-4, 5e-5), betas=(0.62,), inits=(2.0,),
        duration_s=1.0, with_batch=False, check_reference=False, drift_reference=None,
        with_step_touchdown=False, with_penalty_ground=False,
    )  # fmt: skip
    coarse, default = points
    # measured on the 2026-11-25 defaults: 3.2 re-touches per stance at 7.5e-4 s (1.07 at 5e-4,
    # which the older defaults chattered at), 0.18-0.19 on the reference and default
    assert coarse.failure == "contact chatter" and coarse.status == "fails"
    assert coarse.max_retouches is not None and coarse.max_retouches > 1.5
    assert default.failure is None and default.max_retouches is not None
    assert default.max_retouches < 1.0
    assert isinstance(info["reference_retouches_per_stance"], float)

"""The grid's rule for "same gaits": labels, except across the classifier's boundary."""

from __future__ import annotations

from sim_core.model.gait import classify_gait
from sim_core.numerics.convergence import same_gaits


def test_outcomes_straddling_the_classifier_boundary_are_one_gait() -> None:
    ref, run, betas = [2.77, 1.70], [2.79, 1.71], [0.655, 0.655]  # the tripod's edge: 2.78
    assert classify_gait(ref[0], 0.655) != classify_gait(run[0], 0.655)  # the straddle
    assert same_gaits(run, ref, betas)


def test_a_different_attractor_is_a_different_gait() -> None:
    ref, run = [2.05, 1.70], [3.29, 1.70]
    assert not same_gaits(run, ref, [0.655, 0.655])


def test_a_missing_outcome_is_never_the_same_gait() -> None:
    ref: list[float | None] = [2.05]
    run: list[float | None] = [None]
    assert not same_gaits(run, ref, [0.655])


def test_the_solver_options_reach_mujoco_and_the_defaults_are_mujocos() -> None:
    import mujoco

    from sim_core.model.mjspec import build_spec
    from sim_core.model.params import ModelParams

    def opt(**over: object) -> mujoco.MjOption:
        return build_spec(ModelParams.of(**over), visual=False).compile().opt

    d = opt()
    assert d.solver == mujoco.mjtSolver.mjSOL_NEWTON and d.iterations == 100
    assert d.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    assert not d.disableflags & mujoco.mjtDisableBit.mjDSBL_WARMSTART
    o = opt(solver="pgs", solver_iterations=5, cone="pyramidal", warmstart=False)
    assert o.solver == mujoco.mjtSolver.mjSOL_PGS and o.iterations == 5
    assert o.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL
    assert o.disableflags & mujoco.mjtDisableBit.mjDSBL_WARMSTART


def test_a_solver_option_passes_only_within_the_tolerance_and_the_table_says_so() -> None:
    from sim_core.numerics.solver import OptionRow, options_markdown

    rows = [
        OptionRow("default", 0.30, 0.02, True, 0.0, 0.0006, None),
        OptionRow("fast but off", 0.20, 0.09, True, 0.08, 0.002, None),
        OptionRow("other gait", 0.25, 0.01, False, 1.0, 0.001, None),
        OptionRow("breaks", 0.10, None, False, None, None, "flipped"),
    ]
    assert [r.within_tolerance for r in rows] == [True, False, False, False]
    table = options_markdown(rows).splitlines()
    assert "| fast but off | 1.50x |" in table[3] and table[3].endswith("outside tolerance |")
    assert table[5].endswith("| flipped |") and table[2].endswith("| ok |")

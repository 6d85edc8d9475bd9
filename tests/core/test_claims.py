"""The finder's four-check plumbing (`lab/finder_claims.py`) on short runs: what it runs, what
it reports. The numbers themselves come from `python -m lab finder-claims`
(docs/REPRODUCTION.md)."""

from __future__ import annotations

from lab.finder_claims import (
    FOLD_BETAS,
    METACHRONAL_BETAS,
    Variant,
    numerics,
    numerics_report,
    robustness,
    robustness_report,
)
from sim_core.contract.finder import Attractor, CellResult, FinderOutput


def _state(d31: float, confirmed: str) -> Attractor:
    return Attractor(d31=d31, lo=d31, hi=d31, gait="tripod" if d31 > 2.54 else "metachronal",
                     starts=1, runs=1, slope=0.5, slope_pairs=5, max_drift=0.0,
                     confirmed=confirmed)  # type: ignore[arg-type]  # fmt: skip


def test_numerics_reruns_only_the_stable_points_at_the_asked_betas() -> None:
    cells = [
        CellResult(beta=b, body_mass_g=3.0, slope_deg=0.0, borders=[], ghosts=[], runs=[],
                   sim_s=0.0, attractors=[_state(2.95, "both sides"), _state(2.12, "below only")])
        for b in (0.62, 0.66)
    ]  # fmt: skip
    found = FinderOutput(source="test", config={}, cells=cells)
    checks = numerics(found, [0.62], folds=[0.625], duration_s=0.6)
    assert [(c.beta, c.d31) for c in checks] == [(0.62, 2.95)]
    (c,) = checks
    assert c.tol == 0.1  # within 0.01 of a fold
    assert c.end is None and c.end_half is None and not c.same  # 0.6 s never settles
    assert c.landing is None or 0.0 < c.landing < 2.0
    assert "not settled" in numerics_report(checks)[2] and "**no**" in numerics_report(checks)[2]


def test_robustness_runs_each_variant_and_reads_the_fold_bracket() -> None:
    variants = robustness(names=("kp_lift",), scales=(0.9,), duration_s=0.6)
    assert [v.name for v in variants] == ["default", "kp_lift x0.9"]
    assert all(len(v.tripod) == len(FOLD_BETAS) and len(v.metachronal) == len(METACHRONAL_BETAS)
               for v in variants)  # fmt: skip
    assert variants[0].fold() == f"below {FOLD_BETAS[0]:g}"  # nothing settles in 0.6 s
    rows = robustness_report(variants)
    assert len(rows) == 4 and all(r.count("|") == rows[0].count("|") for r in rows)


def test_fold_bracket_text() -> None:
    ends = [2.95, 2.94, 2.95, None, 2.1]
    v = Variant("x", list(zip(FOLD_BETAS, ends, strict=True)), [])
    assert v.fold() == f"{FOLD_BETAS[2]:g}-{FOLD_BETAS[3]:g}"
    gappy = Variant("y", list(zip(FOLD_BETAS, [2.95, None, 2.95, None, None], strict=True)), [])
    assert gappy.fold().endswith("(gaps)")
    assert Variant("z", [(b, 2.95) for b in FOLD_BETAS], []).fold() == f"above {FOLD_BETAS[-1]:g}"

"""Issue 30, point 3: a run the insect could not physically walk is a typed failure with a kind
and a time, never numbers (89.9 deg uphill used to exit 0 at -730 cm/s with 0 touchdowns)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from server.kinds import ComputeSettings, JobFailed, execute, open_compute
from server.kinds.run import RunJob
from sim_core import RunSpec, simulate, simulate_batch
from sim_core.cli.main import main
from sim_core.contract import FAILURE_KINDS, NO_FOOTHOLD_S, SLIDE_BACK_SPEED_M_S
from sim_core.model import guard
from sim_core.model.anatomy import attachment_points, leg_reach
from sim_core.model.params import ModelParams
from sim_core.model.runner import BatchRunner


@pytest.mark.parametrize(
    ("slope", "kind"),
    [(89.9, "sliding_back"), (-80.0, "left_ground"), (-89.9, "no_footholds")],
)
def test_an_impossible_slope_fails_with_its_kind_and_time(slope: float, kind: str) -> None:
    """Measured 2026-11-26 at beta 0.66, 3 g: 89.9 deg slides back at -119 cm/s (fails at
    0.25 s), -80 deg lifts the body beyond the legs' reach (0.42 s), -89.9 deg leaves every leg
    in swing (0.24 s)."""
    r = simulate(RunSpec(beta=0.66, slope_deg=slope, duration_s=1.0))
    assert r.failure is not None, r.summary()
    assert r.failure.kind == kind and kind in FAILURE_KINDS
    assert 0.0 < r.failure.time_s < 1.0
    assert not r.failure.numerical
    s = r.summary()
    assert s["speed_cm_s"] is None and s["d31"] == [] and s["failure"]["kind"] == kind


def test_the_cli_fails_the_89_9_degree_run(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["run", "--beta", "0.66", "--slope-deg", "89.9", "--duration-s", "1", "--json"])
    out = capsys.readouterr().out
    assert code == 1
    assert '"kind": "sliding_back"' in out and '"speed_cm_s": null' in out


def test_the_api_job_fails_the_89_9_degree_run(tmp_path: Path) -> None:
    job = RunJob(beta=0.66, slope_deg=89.9, duration_s=1.0, d31_init=[2.0])
    with pytest.raises(JobFailed) as exc:
        execute(job, open_compute(ComputeSettings(cache_dir=tmp_path), lambda _: None, 1))
    text = str(exc.value)
    assert "slid backwards" in text and "run stopped at t = 0.25" in text
    assert "smaller dt_s will not help" in text


def test_sound_runs_pass_and_the_checks_change_no_number() -> None:
    """Uphill and downhill 20-30 deg at 3 g walk (the envelope the thresholds were chosen
    from), and with the physical checks switched off the same runs give the same bits."""
    specs = [RunSpec(beta=0.62, slope_deg=30.0, duration_s=1.0),
             RunSpec(beta=0.70, slope_deg=-20.0, duration_s=1.0, body_mass_g=6.0)]  # fmt: skip
    checked = simulate_batch(specs, nthread=1)
    assert all(r.failure is None for r in checked), [r.error for r in checked]
    off = BatchRunner(specs, nthread=1)
    off._limits = off._limits._replace(reach=np.inf, no_foothold_s=np.inf, slide_speed=np.inf)
    off.run()
    for i, r in enumerate(checked):
        assert np.array_equal(off.result(i).events.d31, r.events.d31)
        assert np.array_equal(off.result(i).series.body_pos_m, r.series.body_pos_m)


def _guard(
    qpos: np.ndarray, stance: np.ndarray, time: float, footing: guard.Footing
) -> tuple[int, float]:
    p = ModelParams()
    limits = guard.Limits(p.body.body_thickness / 2, 0.5, leg_reach(p), NO_FOOTHOLD_S, 0.25,
                          SLIDE_BACK_SPEED_M_S)  # fmt: skip
    codes, values = np.zeros(1, dtype=np.int64), np.zeros(1)
    warnings = np.zeros((1, 1, 2), dtype=np.int64)
    guard.guard_codes(np.array([0]), qpos[None], np.zeros((1, 6)), warnings,
                      np.zeros((1, 1), dtype=np.int64), stance[None].astype(np.int8), time,
                      attachment_points(p), limits, footing, codes, values)  # fmt: skip
    return int(codes[0]), float(values[0])


def test_the_guard_thresholds_on_synthetic_states() -> None:
    upright = np.array([0.0, 0.0, 6.75e-3, 1.0, 0.0, 0.0, 0.0])
    on = np.ones(6)
    assert _guard(upright, on, 0.1, guard.new_footing(1))[0] == guard.OK
    # a body above the legs' reach (12.95 mm from the attachments) has left the ground
    high = upright.copy()
    high[2] = 14e-3
    assert _guard(high, on, 0.1, guard.new_footing(1))[0] == guard.LEFT_GROUND
    # no leg in stance: fine for a moment, a failure after NO_FOOTHOLD_S
    assert _guard(upright, np.zeros(6), NO_FOOTHOLD_S / 2, guard.new_footing(1))[0] == guard.OK
    code, value = _guard(upright, np.zeros(6), NO_FOOTHOLD_S * 1.01, guard.new_footing(1))
    assert code == guard.NO_FOOTHOLDS and value > NO_FOOTHOLD_S
    # 2 cm back over a 0.25 s window: -8 cm/s; 1 cm: -4 cm/s is still walking
    back = upright.copy()
    back[0] = -0.02
    code, value = _guard(back, on, 0.25, guard.new_footing(1))
    assert code == guard.SLIDING_BACK and value == pytest.approx(-0.08)
    back[0] = -0.01
    assert _guard(back, on, 0.25, guard.new_footing(1))[0] == guard.OK

"""`insect-gait reproduce` without the simulator: analyses on synthetic data with known answers,
the cache and resume, and the whole pipeline on a paper-like toy system (synthetic_gait)."""

import json
from pathlib import Path

import numpy as np
import pytest

from sim_core import RunSpec
from sim_core.contract.finder import Cell, FinderConfig
from sim_core.contract.surface import DriftSurface
from sim_core.docsections import markers
from sim_core.model.gait import stance_intervals
from sim_core.model.ramp import Ramp
from sim_core.paper.analysis import branch_ranges, range_ends, sweep_summary
from sim_core.paper.figures import ReproduceConfig
from sim_core.paper.finder import find
from sim_core.paper.reproduce import DOC_BEGIN, DOC_END, reproduce, table_rows, update_doc
from sim_core.runs.backends import InlineBackend, run_tasks
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import make_chunks, ramp_task, run_task
from tests.core.synthetic_gait import fake_execute, fake_runner

GRID = [round(0.62 + 0.005 * k, 3) for k in range(17)]
REPO = Path(__file__).resolve().parents[2]


# --- the finder on the paper-like toy: folds ---------------------------------------------------
def test_folds_of_a_family_with_known_saddle_nodes() -> None:
    """By construction the metachronal pair is born at beta 0.645 and the tripod pair dies at
    0.67; the finder's attractors along the grid give those folds (paper Fig. 8)."""
    cells = find([Cell(b) for b in GRID], FinderConfig(), fake_runner)
    tripod = branch_ranges(cells, "tripod")
    meta = branch_ranges(cells, "metachronal")
    assert tripod["ranges"] in ([(0.62, 0.67)], [(0.62, 0.665)])
    assert meta["ranges"] in ([(0.645, 0.70)], [(0.65, 0.70)])
    (ft,) = tripod["folds"]
    (fm,) = meta["folds"]
    assert ft["side"] == "upper" and abs(ft["beta"] - 0.67) <= ft["half_width"] + 1e-9
    assert fm["side"] == "lower" and abs(fm["beta"] - 0.645) <= fm["half_width"] + 1e-9
    lo, hi = range_ends(GRID, tripod["ranges"]) or (0, 0)
    assert lo == 0.62 and hi == pytest.approx(0.67, abs=0.005)
    for b, c in zip(GRID, cells, strict=True):  # S U S where both gaits live, else one S
        if b not in (0.645, 0.67):  # at a fold itself the pair is a tangency
            assert c.pattern() == ("S U S" if 0.645 < b < 0.67 else "S"), (b, c.pattern())


# --- sweeps ------------------------------------------------------------------------------------
def _triangle_data(start: float, turn: float, down_at: float, up_at: float, hold: float = 2.0):
    ramp = Ramp("beta", start, turn, hold, 10.0)
    sched = ramp.schedule()
    t = np.arange(0.05, ramp.duration_s, 0.1)
    v = np.array([sched(x) for x in t])
    first = t < ramp.turn_time_s
    # first leg: the start gait until `down_at`; second leg: the other gait until `up_at`
    past_first = (v - down_at) * np.sign(turn - start) >= 0
    back_second = (v - up_at) * np.sign(start - turn) >= 0
    tri = np.where(first, np.where(past_first, 2.9, 1.9), np.where(back_second, 1.9, 2.9))
    return ramp, t, v, tri


def test_sweep_transitions_and_hysteresis_loop_both_directions() -> None:
    ramp, t, v, d = _triangle_data(0.70, 0.62, 0.645, 0.67)  # Fig. 6a: beta down, then up
    s = sweep_summary(t, v, d, ramp.start, ramp.turn, ramp.hold_s, ramp.ramp_s, v)
    (a,) = s["first_leg"]
    (b,) = s["second_leg"]
    assert (a["before"], a["after"]) == ("metachronal", "tripod")
    assert a["value"] == pytest.approx(0.645, abs=0.002)
    assert b["value"] == pytest.approx(0.67, abs=0.002)
    assert s["loop"] is True and s["width"] == pytest.approx(0.025, abs=0.003)
    assert s["gait_at_start"] == "metachronal" and s["gait_at_turn"] == "tripod"
    # Fig. 9a-like: the value rises first (light -> heavy) and the gait switches later going up
    ramp, t, v, d = _triangle_data(1.0, 6.0, 4.5, 2.5)
    s = sweep_summary(t, v, d, ramp.start, ramp.turn, ramp.hold_s, ramp.ramp_s, 0.66)
    assert s["loop"] is True and s["width"] == pytest.approx(2.0, abs=0.1)


def test_switches_in_the_wrong_order_are_not_a_loop_and_no_switch_is_no_width() -> None:
    ramp, t, v, d = _triangle_data(0.70, 0.62, 0.67, 0.645)
    s = sweep_summary(t, v, d, ramp.start, ramp.turn, ramp.hold_s, ramp.ramp_s, v)
    assert s["loop"] is False
    flat = np.full(t.size, 1.9)
    s = sweep_summary(t, v, flat, ramp.start, ramp.turn, ramp.hold_s, ramp.ramp_s, v)
    assert s["first_leg"] == [] and s["width"] is None and s["loop"] is None


def test_settling_during_the_first_hold_is_not_a_transition() -> None:
    ramp, t, v, d = _triangle_data(0.70, 0.62, 0.645, 0.67)
    d = d.copy()
    d[t < 1.0] = 2.9  # starts tripod, settles to metachronal within the hold
    s = sweep_summary(t, v, d, ramp.start, ramp.turn, ramp.hold_s, ramp.ramp_s, v)
    assert len(s["first_leg"]) == 1 and s["first_leg"][0]["after"] == "tripod"


def test_stance_intervals_pair_touchdowns_with_the_next_liftoff_and_clip() -> None:
    iv = stance_intervals([[0.1, 0.5, 0.9]], [[0.3, 0.7]], 0.2, 1.0)
    assert iv == [[(0.2, 0.3), (0.5, 0.7), (0.9, 1.0)]]


# --- tasks, cache, resume ------------------------------------------------------------------------
def test_task_keys_follow_content() -> None:
    a = run_task(RunSpec(beta=0.62, d31_init=1.0, duration_s=1.0))
    assert a.key == run_task(RunSpec(beta=0.62, d31_init=1.0, duration_s=1.0)).key
    assert a.key != run_task(RunSpec(beta=0.62, d31_init=1.1, duration_s=1.0)).key
    from sim_core import ModelParams

    assert a.key != run_task(a.run_spec(), ModelParams.of(kp_lift=1e-3)).key
    r = ramp_task(Ramp("beta", 0.70, 0.62, 1.0, 2.0), RunSpec())
    assert r.kind == "ramp" and r.duration_s == 6.0 and r.key != a.key
    assert hash(r) == hash(ramp_task(Ramp("beta", 0.70, 0.62, 1.0, 2.0), RunSpec()))
    with pytest.raises(ValueError):
        ramp_task(Ramp("beta", 0.70, 1.2, 1.0, 2.0), RunSpec())  # beyond RunSpec's range


def test_cache_round_trip_and_bad_files(tmp_path: Path) -> None:
    cache = ResultCache(tmp_path / "c")
    t = run_task(RunSpec(duration_s=1.0))
    assert cache.get(t) is None
    cache.put(t, {"d31": [1.0, 2.0]})
    assert cache.get(t) == {"d31": [1.0, 2.0]} and t in cache
    assert [p.name for p in (tmp_path / "c").iterdir()] == [f"{t.key}.json"]  # no temp files
    cache.path(t).write_text("{not json")
    assert cache.get(t) is None
    other = run_task(RunSpec(duration_s=2.0))
    cache.path(t).write_text(json.dumps({"task": {"spec": other.spec}, "result": {}}))
    assert cache.get(t) is None  # a file that describes another task is not this result


def test_chunks_group_by_numerics_and_put_long_work_first() -> None:
    short = [run_task(RunSpec(d31_init=x, duration_s=1.0)) for x in (1.0, 2.0, 3.0)]
    other = run_task(RunSpec(duration_s=1.0, dt_s=2.5e-5))
    long = ramp_task(Ramp("beta", 0.70, 0.62, 1.0, 5.0), RunSpec())
    chunks = make_chunks([*short, other, long], chunk_size=8, workers=1)
    assert chunks[0][0] == long and len(chunks[0]) == 4  # one group, longest first
    assert [other] in chunks  # another timestep: its own batch
    assert chunks[0][0] == make_chunks([*short, other, long], chunk_size=1)[0][0]
    assert all(len({t.group() for t in c}) == 1 for c in chunks)
    assert max(len(c) for c in make_chunks(short, chunk_size=8, workers=3)) == 1


class Counting:
    """fake_execute that counts the tasks it runs and can fail after some chunks."""

    def __init__(self, fail_after: int | None = None) -> None:
        self.tasks = 0
        self.chunks = 0
        self.fail_after = fail_after

    def __call__(self, tasks):
        if self.fail_after is not None and self.chunks >= self.fail_after:
            raise KeyboardInterrupt
        self.chunks += 1
        self.tasks += len(tasks)
        return fake_execute(tasks)


def test_interrupted_run_resumes_and_a_rerun_does_no_work(tmp_path: Path) -> None:
    tasks = [run_task(RunSpec(beta=0.66, d31_init=x, duration_s=1.0)) for x in range(6)]
    cache = ResultCache(tmp_path)
    first = Counting(fail_after=2)
    with pytest.raises(KeyboardInterrupt):
        run_tasks(tasks, cache, InlineBackend(), chunk_size=2, progress=False, executor=first)
    assert first.tasks == 4
    second = Counting()
    results, stats = run_tasks(tasks + tasks[:1], cache, InlineBackend(), chunk_size=2,
                               progress=False, executor=second)  # fmt: skip
    assert second.tasks == 2 and (stats.tasks, stats.computed, stats.cached) == (6, 2, 4)
    third = Counting()
    again, stats = run_tasks(tasks, cache, InlineBackend(), progress=False, executor=third)
    assert third.tasks == 0 and stats.cached == 6 and again == results


# --- the whole pipeline on a paper-like system ----------------------------------------------
def test_pipeline_recovers_the_paper_from_a_system_built_like_it(tmp_path: Path) -> None:
    doc = tmp_path / "REPRODUCTION.md"
    surface_begin, surface_end = markers("surface")
    doc.write_text(f"# title\n\n{DOC_BEGIN}\nstale table\n{DOC_END}\n\nkept text\n"
                   f"{surface_begin}\nstale surface\n{surface_end}\n")  # fmt: skip
    count = Counting()
    report = reproduce(["all"], ReproduceConfig(), tmp_path / "fig", tmp_path / "cache",
                       InlineBackend(), doc=doc, progress=False, executor=count)  # fmt: skip
    rows = {r[0]: r for r in table_rows(report.summaries)}
    expected_yes = [
        "Fig. 6a: metachronal → tripod as β decreases",
        "Fig. 6a: tripod → metachronal as β increases",
        "halving the ramp rate moves the transitions by < 0.005 (our check)",
        "Fig. 7: fixed points at β = 0.64",
        "Fig. 7: fixed points at β = 0.655",
        "Fig. 7: fixed points at β = 0.675",
        "Fig. 7: ghost at β = 0.64",
        "Fig. 7: ghost at β = 0.675",
        "Fig. 7: free runs end on the surface's stable zeros (our check)",
        "Fig. 8: tripod stable for β in",
        "Fig. 8: metachronal stable for β in",
        "drift surface: the pin at K/3 and dt/2 on a sample (our check)",
        "Fig. 9a: body mass",
        "Fig. 9b: slope",
        "no phase resetting: Δ31 neutral (Sec. IV)",
    ]
    for label in expected_yes:
        assert rows[label][3] == "yes", rows[label]
    assert rows["Fig. 5: Δ31 at β = 0.62 (tripod)"][3] == "yes"
    names = {p.name for p in (tmp_path / "fig").iterdir()}
    for stem in ("fig5", "fig6a", "fig6b", "fig7", "fig8", "fig9a", "fig9b", "ablation"):
        assert {f"{stem}.png", f"{stem}.json", f"{stem}.csv"} <= names
    assert {"surface.json", "surface_penalty.json", "mechanism.png"} <= names
    surface = DriftSurface.model_validate_json((tmp_path / "fig" / "surface.json").read_text())
    assert surface.betas == list(ReproduceConfig().surface_betas)
    # the toy's folds: metachronal (1.9) born between 0.64 and 0.645, tripod (2.9) gone by 0.67
    folds = {(round(f.d31), f.side): (f.beta_lo, f.beta_hi) for f in surface.folds}
    assert folds[(2, "ends as beta falls")][0] <= 0.645 <= folds[(2, "ends as beta falls")][1]
    assert folds[(3, "ends as beta rises")][0] <= 0.67 <= folds[(3, "ends as beta rises")][1]
    text = doc.read_text()
    assert "kept text" in text and "stale" not in text and "| paper states |" in text
    assert (
        "The protocol on a sample (every difference within the 0.3 mrad noise floor: yes)" in text
    )
    first_pass = len(ReproduceConfig().surface_betas) * len(ReproduceConfig().surface.d31_grid)
    assert count.tasks == report.stats.computed > first_pass  # and bisection, walks, figures
    # a re-run of one figure simulates nothing and keeps the other figures' rows
    again = reproduce(["7"], ReproduceConfig(), tmp_path / "fig", tmp_path / "cache",
                      InlineBackend(), progress=False, executor=count)  # fmt: skip
    assert again.stats.computed == 0 and "fig8" in again.summaries


def test_fig8_alone_runs_without_fig7s_free_runs(tmp_path: Path) -> None:
    """`reproduce --figure 8` from an empty cache: Fig. 8 and the mechanism, and no Fig. 7
    (its free runs are not asked for, so nothing may read them: it raised KeyError before)."""
    count = Counting()
    report = reproduce(["8"], ReproduceConfig(), tmp_path / "fig", tmp_path / "cache",
                       InlineBackend(), progress=False, executor=count)  # fmt: skip
    names = {p.name for p in (tmp_path / "fig").iterdir()}
    assert {"fig8.png", "fig8.json", "fig8.csv", "mechanism.png", "surface.json"} <= names
    assert not {n for n in names if n.startswith("fig7")}
    assert "fig8" in report.summaries and "fig7" not in report.summaries


def test_table_says_not_run_for_missing_figures_and_misses_as_misses() -> None:
    rows = table_rows({})
    assert rows and all(r[2] == "not run" and r[3] == "not run" for r in rows)
    miss = {"fig5": {"0.62": {"target_rad": 2.9, "hits": 0, "runs": 8, "branch_rad": None,
                              "finals": [0.2] * 8, "speed_cm_s": 3.0}}}  # fmt: skip
    rows = {r[0]: r for r in table_rows(miss)}
    assert rows["Fig. 5: Δ31 at β = 0.62 (tripod)"][3] == "**no**"
    assert rows["speed at β = 0.62 (eq. 2)"][3] == "**no**"  # 3.0 vs 3.6 cm/s


def test_doc_update_needs_both_markers_and_the_real_doc_has_them() -> None:
    with pytest.raises(ValueError):
        update_doc("no markers here", "table")
    assert update_doc(f"a{DOC_BEGIN}x{DOC_END}b", "T") == f"a{DOC_BEGIN}\nT\n{DOC_END}b"
    text = (REPO / "docs" / "REPRODUCTION.md").read_text()
    assert text.index(DOC_BEGIN) < text.index(DOC_END)


def test_a_slope_sweep_that_turned_says_so_and_shows_the_paper_ground_beside_it() -> None:
    sweep = {"gait_at_turn": "tripod", "gait_at_start": "metachronal", "loop": True,
             "width": 10.0, "max_heading_deg": 97.0}  # fmt: skip
    held = sweep | {"gait_at_turn": "metachronal", "loop": None, "width": None,
                    "max_heading_deg": 0.8}  # fmt: skip
    rows = {r[0]: r for r in table_rows({"fig9b": sweep | {"paper_ground": held}})}
    ours = rows["Fig. 9b: slope"][2]
    assert "turned up to 97 deg" in ours and "Paper's ground: uphill: metachronal" in ours
    assert ours.count("turned") == 1  # the paper's ground kept its heading (0.8 deg)


def test_reproduce_refuses_a_doc_without_its_sections_before_running(tmp_path: Path) -> None:
    """A doc missing the surface's markers is refused before any simulation (it used to fail
    after the whole run, losing the table's update)."""
    doc = tmp_path / "doc.md"
    doc.write_text(f"{DOC_BEGIN}\n{DOC_END}\n")

    def no_runs(*_: object) -> object:
        raise AssertionError("a simulation ran")

    with pytest.raises(ValueError, match="surface:begin"):
        reproduce(["8"], ReproduceConfig.quick(), tmp_path / "out", tmp_path / "cache",
                  InlineBackend(), doc=doc, progress=False, executor=no_runs)  # fmt: skip

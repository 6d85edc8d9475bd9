"""The settled fixed-point finder on the paper-like toy map (known answers, no simulator) and
the settled rule on synthetic series."""

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from sim_core.contract.finder import Cell, FinderConfig, Probe, RunFn
from sim_core.model.gait import TAIL_DRIFT_SETTLED, settling
from sim_core.paper.finder import find
from sim_core.paper.finder_runs import clusters_of, map_slope, parting, slowest_passage
from tests.core.synthetic_gait import fake_runner

CFG = FinderConfig()


def test_bistable_beta_gives_two_gaits_and_the_bisected_saddle_between() -> None:
    (c,) = find([Cell(0.655)], CFG, fake_runner)
    window = sorted((a for a in c.attractors if 1.4 < a.d31 < 3.4), key=lambda a: a.d31)
    assert [a.gait for a in window] == ["metachronal", "tripod"]
    assert window[0].d31 == pytest.approx(1.9, abs=0.1) and window[1].d31 == pytest.approx(
        2.9, abs=0.1
    )
    assert all(a.slope is not None and 0 <= a.slope < 1 for a in window)
    assert sum(a.starts for a in c.attractors) == CFG.starts and not c.unsettled
    inside = [b for b in c.borders if b.d31 is not None and 1.4 < b.d31 < 3.4]
    (b,) = inside
    assert b.resolved and b.start_hi - b.start_lo <= CFG.border_tol_rad
    assert b.d31 == pytest.approx(2.4, abs=0.05)  # the toy's saddle
    assert b.slope is not None and b.slope > 1  # it repels
    assert c.pattern() == "S U S"


def test_past_a_fold_one_gait_and_its_ghost() -> None:
    (c,) = find([Cell(0.64)], CFG, fake_runner)
    assert [a.gait for a in c.attractors if 1.4 < a.d31 < 3.4] == ["tripod"]
    assert any(abs(g.d31 - 2.1) < 0.15 and abs(g.drift) < 0.02 for g in c.ghosts), c.ghosts


def test_a_run_that_does_not_settle_is_listed_not_guessed() -> None:
    def sliding(batch):  # 1 mrad per cycle forever: no attractor anywhere
        return [{"d31": list((p.d31_init + 0.001 * np.arange(400)) % (2 * math.pi)),
                 "error": None} for _, p in batch]  # fmt: skip

    (c,) = find([Cell(0.66)], FinderConfig(starts=4), sliding)
    assert not c.attractors and not c.borders
    assert len(c.unsettled) == 4 and all("still drifting" in r.why for r in c.unsettled)


def test_failed_runs_are_kept_with_their_failure() -> None:
    (c,) = find(
        [Cell(0.66)], FinderConfig(starts=2), lambda b: [{"d31": [], "error": "flipped"}] * len(b)
    )
    assert [r.failure for r in c.runs] == ["flipped", "flipped"] and not c.attractors


def test_settled_rule() -> None:
    slide = (2.9 - 0.003 * np.arange(200)) % (2 * math.pi)  # a ghost's 3 mrad per cycle
    s = settling(slide)
    assert not s.settled and "drifting" in s.why and s.drift == pytest.approx(-0.003)
    rng = np.random.default_rng(1)
    fixed = (6.27 + 0.002 * rng.standard_normal(200)) % (2 * math.pi)  # across 0 = 2 pi
    s = settling(fixed)
    assert s.settled and s.final is not None and min(s.final, 2 * math.pi - s.final) < 0.05
    assert abs(s.drift or 1) < TAIL_DRIFT_SETTLED
    short = settling(np.full(100, 2.9))  # 25 touchdowns in the last quarter: too short to judge
    assert not short.settled and "run longer" in short.why


def test_pure_helpers() -> None:
    assert [len(c.finals) for c in clusters_of([6.27, 0.01, 2.9, 2.93, 1.9])] == [2, 1, 2]
    x = 2.0 + 0.5 * 0.8 ** np.arange(60)  # approach with slope 0.8 per cycle
    slope, pairs = map_slope([x], 2.0)
    assert slope == pytest.approx(0.8**4, rel=1e-6) and pairs >= 5
    a = 2.4 + 1e-3 * 1.2 ** np.arange(60)  # two runs leaving a saddle at 2.4, one each way
    b = 2.4 - 1e-3 * 1.2 ** np.arange(60)
    dwell, growth = parting(np.clip(a, 0, 6), np.clip(b, 0, 6))
    assert dwell == pytest.approx(2.4, abs=0.01) and growth == pytest.approx(1.2**4, rel=1e-6)
    ghost = np.concatenate([np.linspace(3.5, 3.0, 20), np.full(60, 3.0) - 1e-4 * np.arange(60),
                            np.linspace(2.99, 2.0, 40), np.full(100, 2.0)])  # fmt: skip
    g = slowest_passage(ghost, 2.0)
    assert g is not None and g.d31 == pytest.approx(3.0, abs=0.02) and g.cycles >= 20


def map_runner(
    step: Callable[[float, float], float], calls: list[tuple[Cell, Probe]] | None = None
) -> RunFn:
    """A `run` on a one-dimensional map x <- x + step(x, beta), 400 cycles per run."""

    def run(batch: list[tuple[Cell, Probe]]) -> list[dict[str, Any]]:
        if calls is not None:
            calls.extend(batch)
        out: list[dict[str, Any]] = []
        for cell, probe in batch:
            x, xs = probe.d31_init, list[float]()
            for _ in range(400):
                xs.append(x % (2 * math.pi))
                x += float(np.clip(step(x, cell.beta), -0.3, 0.3))
            out.append({"d31": xs, "error": None})
        return out

    return run


def test_kicks_confirm_a_stable_state_from_both_sides() -> None:
    (c,) = find([Cell(0.655)], CFG, fake_runner)
    window = [a for a in c.attractors if 1.4 < a.d31 < 3.4]
    assert window and all(a.confirmed == "both sides" and a.stable for a in window)
    assert all(a.kicks == (CFG.kick_rad, CFG.kick_rad) for a in window)
    assert sum(r.role == "kick" for r in c.runs) >= 2 * len(c.attractors)


def test_a_state_that_attracts_from_below_only_is_not_called_stable() -> None:
    # x = 2 attracts from below and repels above (a semi-stable point); 2.6 attracts both ways
    def step(x: float, beta: float) -> float:
        return 0.6 * (x - 2.0) ** 2 * (2.6 - x)

    (c,) = find([Cell(0.66)], FinderConfig(max_borders=0), map_runner(step))
    by_place = {round(a.d31, 1): a for a in c.attractors}
    assert by_place[2.0].confirmed == "below only" and not by_place[2.0].stable
    assert by_place[2.6].confirmed == "both sides"
    assert [round(a.d31, 1) for a in c.stable()] == [2.6] and c.pattern() == "S"
    assert [round(a.d31, 1) for a in c.one_sided()] == [2.0]


def test_a_thin_basin_missed_by_the_spread_starts_is_found_from_a_neighbour() -> None:
    # a state at 4.7: its basin is 3.7-5.7 at beta 0.60 but only 4.6-4.8 at 0.61, between the
    # spread starts (4.32, 5.11); elsewhere everything goes to 2.6 (above the basin, upward
    # round the circle, so no run passes through it)
    def step(x: float, beta: float) -> float:
        half = 1.0 if beta < 0.605 else 0.1
        if abs(x - 4.7) < half:
            return 0.3 * (4.7 - x)
        return 0.3 * (2.6 + (2 * math.pi if x > 4.7 else 0.0) - x)

    cells = [Cell(0.60), Cell(0.61)]
    alone = find(cells, replace(CFG, max_borders=0, kick_rad=0.0, neighbour_seeds=False),
                 map_runner(step))  # fmt: skip
    assert [round(a.d31, 1) for a in alone[1].attractors] == [2.6]
    calls: list[tuple[Cell, Probe]] = []
    cfg = replace(CFG, max_borders=0, kick_rad=0.0)
    seeded = find(cells, cfg, map_runner(step, calls))
    at_061 = {round(a.d31, 1): a for a in seeded[1].attractors}
    assert set(at_061) == {2.6, 4.7} and at_061[4.7].starts == 0  # reached by the seed only
    assert [r.role for r in seeded[1].runs if r.attractor is not None and
            round(seeded[1].attractors[r.attractor].d31, 1) == 4.7] == ["seed"]  # fmt: skip
    assert len(calls) == len(set(calls))  # a probe asked twice is run once
    # and on to the next beta, which only the seeded neighbour found it from
    chain = find([*cells, Cell(0.62)], cfg, map_runner(step))
    assert {round(a.d31, 1) for a in chain[2].attractors} == {2.6, 4.7}


def test_a_bisection_run_on_a_known_third_state_adds_no_second_copy() -> None:
    # 1.9 (metachronal) below 2.3, 2.9 (tripod) above 2.4, and a sliver 2.3-2.4 that jumps to
    # 4.6, a state the start 4.32 reaches too: the border 1.96 | 2.75 runs into it
    def run(batch: list[tuple[Cell, Probe]]) -> list[dict[str, Any]]:
        out: list[dict[str, Any]] = []
        for _, p in batch:
            x = p.d31_init
            if 2.3 <= x < 2.4 or 3.6 <= x < 5.6:
                end = 4.6
            else:
                end = 1.9 if x < 2.3 or x >= 5.6 else 2.9
            out.append({"d31": [x] + [end] * 399, "error": None})
        return out

    (c,) = find([Cell(0.66)], FinderConfig(kick_rad=0.0), run)
    places = sorted(round(a.d31, 2) for a in c.attractors)
    assert places == [1.9, 2.9, 4.6], places
    assert any("third state" in b.note for b in c.borders)


def test_a_short_run_re_run_longer_is_not_listed_as_unsettled() -> None:
    from sim_core.contract.finder import CellResult, RunOutcome

    def out(x: float, dur: float, settled: bool) -> RunOutcome:
        why = "" if settled else "drifting"
        return RunOutcome(d31_init=x, duration_s=dur, final=2.0, drift=0.0, settled=settled,
                          why=why, attractor=None, role="kick")  # fmt: skip

    c = CellResult(beta=0.66, body_mass_g=3.0, slope_deg=0.0, attractors=[], borders=[],
                   ghosts=[], sim_s=0.0,
                   runs=[out(2.0, 20.0, False), out(2.0, 40.0, True), out(2.5, 20.0, False),
                         out(2.5, 40.0, False)])  # fmt: skip
    assert [(r.d31_init, r.duration_s) for r in c.unsettled] == [(2.5, 40.0)]

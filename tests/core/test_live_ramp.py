"""One ramp driver: the live Simulation (the viewer's ramps) ramps exactly as the reproduction's
tasks do, and records what was in force at each Delta31 event (one history, in the core)."""

from __future__ import annotations

from sim_core import RunSpec, Simulation
from sim_core.contract import EventConditions, Ramp, RampParam
from sim_core.runs.tasks import execute_chunk, ramp_task


def test_a_live_ramp_is_the_tasks_ramp_and_its_record_names_each_phase() -> None:
    ramp = Ramp("beta", 0.66, 0.62, 0.2, 0.4)
    spec = RunSpec(beta=0.66, d31_init=2.5)
    (task,) = execute_chunk([ramp_task(ramp, spec)])

    sim = Simulation(spec)
    sim.start_ramp(ramp)
    assert sim.ramp == ramp and sim.ramp_phase == "hold" and sim.ramp_started_at_s == 0.0
    sim.advance(ramp.duration_s)
    # the same driver, the same physics: every Delta31 event equal, bit for bit
    assert [d for _, d in sim.d31_events] == task["d31"]
    assert [t for t, _ in sim.d31_events] == task["d31_times_s"]
    at = sim.d31_conditions
    assert len(at) == len(sim.d31_events)
    phases = [c.ramp for c in at]
    assert [p for k, p in enumerate(phases) if k == 0 or p != phases[k - 1]] == [
        "hold", "down", "up", "hold"
    ]  # fmt: skip
    assert all(c.ramp_param == "beta" and c.ground == "constraint" for c in at)
    assert min(c.beta for c in at) < 0.63 and at[0].beta == 0.66

    sim.advance(0.1)  # past its end: the ramp is over, beta back at its start
    assert sim.ramp is None and sim.ramp_phase == "" and sim.beta == 0.66
    assert sim.d31_conditions[-1] == EventConditions(0.66, 3.0, 0.0, "constraint")


def test_a_ramp_started_mid_walk_is_at_its_start_value_from_the_next_period() -> None:
    sim = Simulation(RunSpec(beta=0.66, d31_init=2.5, body_mass_g=5.5))
    sim.advance(0.5123)  # not a multiple of the ramp's update period
    n = len(sim.d31_events)
    sim.start_ramp(Ramp("body_mass_g", 3.0, 5.0, 0.25, 1.0))
    assert sim.body_mass_g == 3.0  # set at once, not at the driver's next update
    sim.advance(0.3)
    after = sim.d31_conditions[n:]
    assert after and all(c.ramp == "hold" and c.body_mass_g == 3.0 for c in after), after


def test_a_stopped_ramp_leaves_its_value_and_a_reset_ends_it() -> None:
    sim = Simulation(RunSpec(beta=0.66, d31_init=2.5))
    sim.start_ramp(Ramp("body_mass_g", 3.0, 5.0, 0.0, 1.0))
    sim.advance(0.5)
    sim.stop_ramp()
    left = sim.body_mass_g
    assert 3.5 < left < 4.5 and sim.ramp is None
    sim.advance(0.1)
    assert sim.body_mass_g == left and sim.d31_conditions[-1].ramp == ""
    sim.start_ramp(Ramp("slope_deg", 0.0, 10.0, 0.0, 1.0))
    sim.reset(d31_init=3.0)
    assert sim.ramp is None and sim.d31_events == [] and sim.d31_conditions == []


def test_one_typed_call_sets_each_live_parameter_and_refuses_other_names() -> None:
    """`Simulation.set(param, value)`: the viewer's one way to a live parameter (the ramp's
    names, `RampParam`); `get` reads it back; RunSpec's range and the names are checked."""
    import pytest

    sim = Simulation(RunSpec(beta=0.66, d31_init=2.5))
    values: tuple[tuple[RampParam, float], ...] = (
        ("beta", 0.63), ("body_mass_g", 4.5), ("slope_deg", -7.5)
    )  # fmt: skip
    for param, value in values:
        sim.set(param, value)
        assert sim.get(param) == value
    assert (sim.beta, sim.body_mass_g, sim.slope_deg) == (0.63, 4.5, -7.5)
    sim.advance(0.2)
    assert sim.d31_conditions[-1] == EventConditions(0.63, 4.5, -7.5, "constraint")
    with pytest.raises(ValueError, match="no live parameter 'duration_s'"):
        sim.set("duration_s", 1.0)  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        sim.set("beta", 2.0)  # outside RunSpec's range
    assert sim.beta == 0.63

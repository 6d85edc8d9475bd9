"""ModelParams grouped by concern, its contact one of two grounds, and each parameter still
addressed by its unique leaf name (the edges, the studies and the cache key use it)."""

import json

import pytest
from pydantic import ValidationError

from sim_core.model.params import (
    GROUND_ONLY,
    ConstraintContact,
    ModelParams,
    PenaltyContact,
    parameter_table,
)
from sim_core.runs.tasks import params_json


def test_leaves_build_and_read_the_groups() -> None:
    p = ModelParams.of(friction=0.8, kp_lift=4e-3, dt=2.5e-5)
    assert (p.contact.friction, p.joints.kp_lift, p.numerics.dt) == (0.8, 4e-3, 2.5e-5)
    assert p.leaf("kp_lift") == 4e-3
    grouped = ModelParams.model_validate(
        {"joints": {"kp_lift": 4e-3}, "friction": 0.8, "dt": 2.5e-5}
    )
    assert grouped == p
    with pytest.raises(KeyError, match="no parameter"):
        p.replace(no_such_thing=1.0)


def test_a_ground_takes_only_its_own_constants() -> None:
    assert isinstance(ModelParams().contact, ConstraintContact)
    penalty = ModelParams.of(ground="penalty", ground_stiffness=3000.0)
    assert isinstance(penalty.contact, PenaltyContact)
    assert penalty.contact.ground_stiffness == 3000.0
    with pytest.raises(ValidationError, match="ground_stiffness"):
        ModelParams.of(ground_stiffness=3000.0)  # the default ground has no springs
    with pytest.raises(ValidationError, match="contact_timeconst"):
        ModelParams.of(ground="penalty", contact_timeconst=1e-3)
    with pytest.raises(KeyError, match="constraint ground"):
        ModelParams().leaf("ground_damping")
    assert GROUND_ONLY["penalty"] >= {"ground_stiffness", "ground_tangential_damping"}
    assert "friction" not in GROUND_ONLY["penalty"] | GROUND_ONLY["constraint"]


def test_replace_switches_ground_keeping_what_both_share() -> None:
    p = ModelParams.of(friction=0.7, contact_timeconst=1e-3)
    q = p.replace(ground="penalty", ground_damping=0.2)
    assert isinstance(q.contact, PenaltyContact)
    assert (q.contact.friction, q.contact.ground_damping) == (0.7, 0.2)
    back = q.replace(ground="constraint")
    assert isinstance(back.contact, ConstraintContact)
    assert back.contact.contact_timeconst == ConstraintContact().contact_timeconst  # default again
    with pytest.raises(KeyError, match="penalty ground"):
        q.replace(contact_dmin=0.5)


def test_the_key_part_is_the_flat_one_it_always_was() -> None:
    # the flat model's non-default dumps, as the result cache has always keyed them
    assert params_json(None) == "{}"
    assert params_json(ModelParams.of(ground="penalty")) == '{"ground":"penalty"}'
    p = ModelParams.of(ground="penalty", ground_stiffness=3000.0, friction=0.8)
    assert json.loads(params_json(p)) == {"friction": 0.8, "ground": "penalty",
                                          "ground_stiffness": 3000.0}  # fmt: skip
    assert params_json(ModelParams.of(ground="constraint")) == "{}"


def test_the_table_lists_each_parameter_once_with_the_other_grounds_default() -> None:
    rows = {row.name: row for row in parameter_table()}
    assert rows["ground_stiffness"].group == "contact (penalty ground)"
    assert rows["ground_stiffness"].value == PenaltyContact.model_fields["ground_stiffness"].default
    assert rows["friction"].group == "contact" and rows["ground"].value == "constraint"
    on_penalty = {row.name: row for row in parameter_table(ModelParams.of(ground="penalty"))}
    assert on_penalty["ground"].value == "penalty"

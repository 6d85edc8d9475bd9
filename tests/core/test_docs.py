"""docs/MODEL.md lists every parameter with the value and reason the code uses."""

from pathlib import Path

from sim_core.docsections import update_parameter_doc
from sim_core.model.params import ModelParams, parameter_table

DOC = Path(__file__).resolve().parents[2] / "docs" / "MODEL.md"


def test_model_doc_table_is_current() -> None:
    text = DOC.read_text()
    assert text == update_parameter_doc(text), (
        "docs/MODEL.md is stale: run `insect-gait params --update-doc docs/MODEL.md`"
    )


def test_every_parameter_has_an_origin_and_a_reason() -> None:
    for name, _, origin, reason in parameter_table():
        assert origin in ("paper", "invented"), name
        assert len(reason) > 10, name
    assert len(ModelParams.model_fields) == len(parameter_table())

"""docs/MODEL.md lists every parameter with the value and reason the code uses."""

from pathlib import Path

from sim_core.docsections import update_parameter_doc
from sim_core.model.params import GROUP_OF, PARAMETER_NAMES, parameter_table

DOC = Path(__file__).resolve().parents[2] / "docs" / "MODEL.md"


def test_model_doc_table_is_current() -> None:
    text = DOC.read_text()
    assert text == update_parameter_doc(text), (
        "docs/MODEL.md is stale: run `insect-gait params --update-doc docs/MODEL.md`"
    )


def test_every_parameter_has_an_origin_and_a_reason() -> None:
    for name, group, _, origin, reason in parameter_table():
        assert origin in ("paper", "invented"), name
        assert len(reason) > 10, name
        assert GROUP_OF[name] == group.split(" ")[0]  # "contact (penalty ground)"
    assert [row.name for row in parameter_table()] == list(PARAMETER_NAMES)
    n = len(PARAMETER_NAMES)
    assert n == len(set(PARAMETER_NAMES)) == 78  # every parameter once, by a unique name

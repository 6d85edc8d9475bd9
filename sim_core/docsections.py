"""Generated sections of the markdown documents: tables a command rewrites between two markers.

A document holds `<!-- NAME:begin -->` and `<!-- NAME:end -->`; the command that owns NAME
(params, reproduce, numerics) replaces what lies between them and leaves the prose around
them alone, so measured tables never drift from the code that measured them.
"""

from __future__ import annotations

from sim_core.model.params import ModelParams, parameter_table


def markers(name: str) -> tuple[str, str]:
    return f"<!-- {name}:begin -->", f"<!-- {name}:end -->"


def replace_section(text: str, name: str, body: str) -> str:
    """`text` with the NAME section's content replaced by `body` (both markers must be present,
    in order)."""
    begin, end = markers(name)
    if begin not in text or end not in text.split(begin, 1)[1]:
        raise ValueError(f"the document has no {begin} ... {end} section")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    return f"{head}{begin}\n{body}\n{end}{tail}"


def parameter_markdown(params: ModelParams | None = None) -> str:
    """The parameter table of docs/MODEL.md (kept in sync by a test)."""
    lines = ["| parameter | group | value (SI) | origin | reason |", "|---|---|---|---|---|"]
    for name, group, value, origin, reason in parameter_table(params):
        shown = f"{value:.6g}" if isinstance(value, float) else str(value)
        lines.append(f"| `{name}` | {group} | {shown} | {origin} | {reason} |")
    return "\n".join(lines)


def update_parameter_doc(text: str, params: ModelParams | None = None) -> str:
    """Replace the table between the params markers of a markdown document."""
    return replace_section(text, "params", parameter_markdown(params))

"""The run's options on every command that simulates: RunSpec's fields as flags, bar those a
command varies itself; what was given, checked in RunSpec's words; and the tag that names a
file made with anything but the defaults.

Why one place: `run`, `return-map`, `converge`, `surface`, `surface-check`, `atlas` and
`finder` all take the run's shared options. Generated here from RunSpec (`add_field_flags`),
a new field of it is a new flag of each, with its words and default, and reaches the core
through each command's fields (`run_fields`) with no other file edited. A command leaves out
only what it sets per run itself (`vary`: beta over a list, the starts, the surface's pin, the
finder's run lengths), so a flag never stands for a value the command would overwrite.
"""

from __future__ import annotations

import argparse
import hashlib
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from sim_core.cli.common import UsageError
from sim_core.cli.fields import add_field_flags, flag, given
from sim_core.contract import ModelChoice
from sim_core.model.params import ModelParams
from sim_core.model.spec import RunSpec
from sim_core.runs.keys import canonical

# the condition a search's cell or a surface's row is at besides beta (the finder's `Cell`,
# the surface's `Condition`); a command passes them there and the rest to every run
CONDITION_FIELDS = ("body_mass_g", "slope_deg")


def null_means() -> dict[str, str]:
    """What a null field of RunSpec stands for, as every command's help says it."""
    d = ModelParams().numerics
    return {
        "integrator": f"the model's, {d.integrator}",
        "dt_s": f"the model's, {d.dt:g}",
        "control_dt_s": f"the model's, {d.control_dt:g}",
        "pin_d31": "off (the paper's model)",
    }


def add_run_flags(
    parser: argparse.ArgumentParser,
    *,
    vary: Iterable[str] = (),
    required: tuple[str, ...] = (),
    defaults: dict[str, str] | None = None,
) -> list[str]:
    """A flag per RunSpec field but those in `vary` (what the command sets per run itself);
    `defaults` words a default the command supplies itself when the flag is absent. The field
    names go to `args.run_fields` (read back by `run_fields`)."""
    names = add_field_flags(parser, RunSpec, skip=tuple(vary), required=required,
                            defaults=defaults, null_means=null_means())  # fmt: skip
    parser.set_defaults(run_fields=names)
    return names


def run_fields(args: argparse.Namespace) -> dict[str, Any]:
    """The RunSpec fields the person gave (the flags default to nothing: RunSpec fills the
    rest)."""
    return given(args, args.run_fields)


def validation_message(exc: ValidationError, flags: Mapping[str, str] | None = None) -> str:
    """Each refused option with pydantic's words and the field's range and reason, as RunSpec
    describes it (the REST API refuses the same values with the same bounds); `flags` names
    a field whose command calls its flag otherwise (bench's --sim-seconds: duration_s)."""
    parts = []
    for err in exc.errors():
        field = ".".join(str(x) for x in err["loc"])
        msg = str(err["msg"]).removeprefix("Value error, ")
        if not field:  # a rule across fields: its words name them
            parts.append(msg)
            continue
        info = RunSpec.model_fields.get(field)
        what = f" ({info.description})" if info is not None and info.description else ""
        parts.append(f"{(flags or {}).get(field) or flag(field)}: {msg}{what}")
    return "; ".join(parts)


def split_condition(fields: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """The given run fields split as the searches take them: (the condition, CONDITION_FIELDS;
    the rest, shared by every run)."""
    at = {k: v for k, v in fields.items() if k in CONDITION_FIELDS}
    return at, {k: v for k, v in fields.items() if k not in CONDITION_FIELDS}


def check_runs(fields: Mapping[str, Any], flags: Mapping[str, str] | None = None) -> RunSpec:
    """The spec of `fields` (the command's own values with the person's), or a UsageError in
    RunSpec's words naming each refused flag."""
    try:
        return RunSpec(**fields)
    except ValidationError as exc:
        raise UsageError(validation_message(exc, flags)) from None


def off_defaults(fields: Mapping[str, Any]) -> dict[str, Any]:
    """The given RunSpec fields whose values are not RunSpec's defaults."""
    return {k: v for k, v in fields.items() if v != RunSpec.model_fields[k].default}


def output_tag(fields: Mapping[str, Any], choice: ModelChoice) -> str:
    """What a file's name gains when its runs are not the defaults' (the ground aside, which
    names such files already): "" for the defaults, so their files keep their names (the
    docs and the viewer read them); "-SETTING" for a named setting alone; otherwise
    "[-SETTING]-HASH", 8 hex digits of the leaves off their defaults and the run fields off
    theirs, so two different choices never write one file and equal ones share it."""
    leaves, run = choice.changed(), off_defaults(fields)
    if not leaves and not run:
        return ""
    words = [choice.setting] if choice.setting else []
    if run or leaves != ModelChoice(ground=choice.ground, setting=choice.setting).changed():
        digest = hashlib.sha256(canonical({"params": leaves, "run": run}).encode())
        words.append(digest.hexdigest()[:8])
    return "-" + "-".join(words)


def tagged(path: Path, tag: str) -> Path:
    """`path` with `tag` (`output_tag`) before its suffix: surface_atlas_mass_constraint.json
    -> surface_atlas_mass_constraint-soft_legs.json; unchanged for the defaults' ""."""
    return path.with_name(path.stem + tag + path.suffix)


def provenance_fields(fields: Mapping[str, Any], choice: ModelChoice) -> dict[str, Any]:
    """What a file made with other than the defaults records of how (a free-form config's
    entries): the ground, setting, leaves and run fields that are not the defaults' (empty
    for the defaults, whose files stay as they were)."""
    record = {
        "ground": choice.ground if choice.ground != ModelChoice().ground else None,
        "setting": choice.setting,
        "params": choice.changed(),
        "run": off_defaults(fields),
    }
    return {k: v for k, v in record.items() if v}

"""The model parameters on a command line: `--ground`, `--setting NAME`, `--param NAME=VALUE`
(repeatable), read into the contract's `ModelChoice`, the type every job and the viewer take.

Defined once here for `insect-gait run` and `insect-gait viewer` (a plug-in: it imports
`add_model_args` and `choice_from_args` from `sim_core.cli`), so both parse, check and word the
same flags alike, and alike with the REST API's `params` (the same validator).
"""

from __future__ import annotations

import argparse
from typing import Any

from pydantic import ValidationError

from sim_core.cli.common import UsageError
from sim_core.contract import GROUND_DEFAULT, GROUND_HELP, GROUNDS, ModelChoice

# a ModelChoice field -> its flag
FLAGS = {"ground": "--ground", "setting": "--setting", "params": "--param"}
WORDS = {"true": True, "on": True, "false": False, "off": False}


def add_model_args(parser: argparse.ArgumentParser) -> None:
    """Add --ground, --setting and --param to a command's parser."""
    parser.add_argument("--ground", choices=GROUNDS, default=GROUND_DEFAULT,
                        help=f"{GROUND_HELP} (docs/MODEL.md; default: %(default)s)")  # fmt: skip
    parser.add_argument(
        "--setting", metavar="NAME", default=None,
        help=ModelChoice.model_fields["setting"].description,
    )  # fmt: skip
    parser.add_argument(
        "--param", metavar="NAME=VALUE", action="append", default=[], dest="param",
        help="a model parameter by its leaf name (`insect-gait params` lists them), e.g. "
        "--param kp_lift=1e-3; repeatable, on top of --setting; true/false for a switch",
    )  # fmt: skip


def leaf_value(text: str) -> float | int | str | bool:
    """A typed value as a person writes it: true/false (on/off), an integer, a number, else
    the word itself (a choice such as `solver=cg`); the model checks its type and range."""
    low = text.strip().lower()
    if low in WORDS:
        return WORDS[low]
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text.strip()


def choice_from_args(args: argparse.Namespace) -> ModelChoice:
    """The command line's model parameters, validated; a UsageError naming the flag and the
    leaf otherwise (one line)."""
    params: dict[str, float | int | str | bool] = {}
    for item in args.param:
        name, eq, value = item.partition("=")
        name = name.strip()
        if not eq or not name or not value.strip():
            raise UsageError(f"--param {item!r}: write NAME=VALUE, e.g. kp_lift=1e-3")
        if name in params:
            raise UsageError(f"--param {name}: given twice")
        params[name] = leaf_value(value)
    try:
        return ModelChoice(ground=args.ground, setting=args.setting, params=params)
    except ValidationError as exc:
        parts = []
        for err in exc.errors():
            where = FLAGS.get(str(err["loc"][0]), str(err["loc"][0])) if err["loc"] else ""
            msg = str(err["msg"]).removeprefix("Value error, ")
            parts.append(f"{where}: {msg}" if where else msg)
        raise UsageError("; ".join(parts)) from None


def model_line(choice: ModelChoice) -> str:
    """The line a command prints under its output when the model is not the defaults
    ("model: soft_legs (kp_lift 0.00077, ...)"), else ""."""
    return f"model: {choice.words()}" if choice.changed() or choice.setting else ""


def model_json(choice: ModelChoice) -> dict[str, Any]:
    """The model in a command's --json output: the choice's fields and the leaves it changes."""
    return choice.body() | {"changed": choice.changed()}

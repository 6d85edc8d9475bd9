"""Command-line flags generated from a pydantic model's fields: one schema, every edge.

`RunSpec` declares each run option once (name, type, bounds in its description, default); the
`run` command's flags are made from those fields here, so a new field is a new flag with its
help and default and no hand-written line. Flags default to `argparse.SUPPRESS`: only what the
person typed reaches the model, and the model's own defaults fill the rest (the help shows
them, written as a person would: "2 pi/3 = 2.094", "the model's: implicitfast").
"""

from __future__ import annotations

import argparse
import math
import types
from typing import Any, Literal, Union, get_args, get_origin

from pydantic import BaseModel
from pydantic.fields import FieldInfo

# Defaults a person recognises by name (the initial Delta31 of the metachronal gait, ...)
NAMED = {2 * math.pi / 3: "2 pi/3", math.pi: "pi", 2 * math.pi: "2 pi", 4 * math.pi / 3: "4 pi/3"}


def flag(name: str) -> str:
    """The flag of a field: `d31_init` -> `--d31-init`."""
    return "--" + name.replace("_", "-")


def shown(value: Any, null: str = "none") -> str:
    """A default as a person writes it."""
    if value is None:
        return null
    if isinstance(value, bool):
        return "on" if value else "off"
    if isinstance(value, float):
        for v, name in NAMED.items():
            if math.isclose(value, v, rel_tol=1e-12):
                return f"{name} = {value:.3f}"
        return f"{value:g}"
    return str(value)


def _kind(annotation: Any) -> tuple[type, tuple[Any, ...] | None]:
    """(the value type, its choices or None) of a field's annotation, None stripped."""
    args = get_args(annotation)
    if get_origin(annotation) in (Union, types.UnionType):
        inner = [a for a in args if a is not type(None)]
        return _kind(inner[0]) if len(inner) == 1 else (str, None)
    if get_origin(annotation) is Literal:
        return type(args[0]), args
    return annotation, None


def add_field_flags(
    parser: argparse.ArgumentParser,
    model: type[BaseModel],
    *,
    required: tuple[str, ...] = (),
    skip: tuple[str, ...] = (),
    defaults: dict[str, str] | None = None,
    null_means: dict[str, str] | None = None,
) -> list[str]:
    """A flag per field of `model` (bar `skip`); returns the field names given flags.

    `defaults`: a field's default described in words where the command does something of its
    own when the flag is absent; `null_means`: what a null default stands for (a field whose
    null means "the model's choice").
    """
    names = []
    for name, info in model.model_fields.items():
        if name in skip:
            continue
        names.append(name)
        parser.add_argument(flag(name), **_argument(name, info, name in required,
                                                    (defaults or {}).get(name),
                                                    (null_means or {}).get(name)))  # fmt: skip
    return names


def _argument(
    name: str, info: FieldInfo, required: bool, default_words: str | None, null: str | None
) -> dict[str, Any]:
    kind, choices = _kind(info.annotation)
    words = info.description or name.replace("_", " ")
    if required:
        default = "required"
    elif default_words is not None:
        default = default_words
    else:
        default = shown(info.default, null or "none")
    help_text = f"{words} (default: {default})".replace("%", "%%")
    out: dict[str, Any] = {"dest": name, "default": argparse.SUPPRESS, "help": help_text}
    if required:
        out["required"] = True
    if kind is bool:
        out["action"] = argparse.BooleanOptionalAction
    elif choices is not None:
        out["choices"] = choices
    else:
        out["type"] = kind
        out["metavar"] = name.upper()
    return out


def given(args: argparse.Namespace, names: list[str]) -> dict[str, Any]:
    """The fields the person gave on the command line (the flags default to SUPPRESS)."""
    return {n: getattr(args, n) for n in names if hasattr(args, n)}

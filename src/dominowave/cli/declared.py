"""Command-line options generated from declared parameters (:mod:`dominowave.params`).

A parameter class (e.g. :class:`dominowave.chain.ChainParams`) declares each field once:
default, unit, description, range and concern (``group``). :func:`parameter_options`
turns those declarations into typer options: the option is the field's name with dashes
(``d_over_l`` -> ``--d-over-l``; a few keep a shorter name given in ``renamed``), its
help the description followed by the unit and the default, its help panel the field's
concern. Every such option defaults to None, "not given": the class fills in its own
default, and a command can tell a value given on the command line from a default.

:func:`with_options` gives a command function those options besides its own: typer
builds a command from a function's signature, so the function takes the fields as
``**fields`` and its ``__signature__`` lists them. :class:`PanelledCommand` draws the
help of such a command with rich, one panel per concern, with the help texts taken
as plain text (rich markup would read the units ``[m]`` as tags and drop them).
"""

from __future__ import annotations

import dataclasses
import inspect
import math
import re
import types
import typing
from collections.abc import Callable, Mapping
from typing import Annotated, Any

import typer
from rich.markup import escape
from typer.core import TyperCommand

from dominowave.params import ParameterSpec, parameter_specs

__all__ = [
    "PanelledCommand",
    "help_text",
    "option_error",
    "option_name",
    "parameter_options",
    "with_options",
]


def option_name(name: str, renamed: Mapping[str, str] | None = None) -> str:
    """``--field-name`` of field ``name`` (or its name in ``renamed``)."""
    return "--" + (renamed or {}).get(name, name).replace("_", "-")


def option_error(
    exc: ValueError, fields: typing.Collection[str], renamed: Mapping[str, str] | None = None
) -> ValueError:
    """``exc`` in the words of the command line: each ``name = value`` of one of the
    ``fields`` in its message (as :mod:`dominowave.checks` writes them) reads
    ``--name = value``, the option that sets it; any other message is kept."""
    message = str(exc)

    def as_option(match: re.Match) -> str:
        name = match.group(1)
        return f"{option_name(name, renamed)} = " if name in fields else match.group(0)

    named = re.sub(r"(?<![\w-])([a-z_][a-z0-9_]*) = ", as_option, message)
    return exc if named == message else ValueError(named)


def _value_text(value: Any) -> str:
    if isinstance(value, float):
        return "inf" if math.isinf(value) else f"{value:g}"
    return str(value)


def help_text(field: dataclasses.Field, spec: ParameterSpec, flag: str) -> str:
    """The description, then ``[unit; default X]`` (unit if any): a field that is not set
    by default says so, unless its description already says what not setting it means
    (``not set: ...``). ``flag`` is the option's name (a switch's default is named by it:
    ``default --held``)."""
    default = field.default
    parts = [spec.unit] if spec.unit else []
    if isinstance(default, bool):
        parts.append(f"default {flag}" if default else f"default --no-{flag[2:]}")
    elif default is not None:
        parts.append(f"default {_value_text(default)}")
    elif "not set" not in spec.doc:
        parts.append("not set by default")
    return spec.doc + (f" [{'; '.join(parts)}]" if parts else "")


def _option_type(hint: Any, spec: ParameterSpec) -> type:
    """The type the command line parses: a categorical field is text (its class names the
    valid choices when a value is not one of them), an optional field its value's type,
    a field of several types (e.g. a number or a word) text that the command reads."""
    if spec.choices is not None:
        return type(spec.choices[0])
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        kinds = [a for a in typing.get_args(hint) if a is not type(None)]
        return kinds[0] if len(kinds) == 1 else str
    return hint


def parameter_options(
    cls: type,
    *,
    renamed: Mapping[str, str] | None = None,
    panels: Mapping[str, str] | None = None,
) -> list[inspect.Parameter]:
    """Keyword parameters of a command, one typer option per declared field of ``cls``.

    ``renamed`` maps a field to its option's name where the two differ (``n_dominoes``:
    ``n`` gives ``--n``); ``panels`` a field's ``group`` to the title of its help panel
    (default: the group's name, capitalised). Each parameter is named after its field,
    defaults to None ("not given") and has the field's type; a ``bool`` field is a switch
    ``--name/--no-name``.
    """
    hints = typing.get_type_hints(cls)
    out = []
    for name, (field, spec) in parameter_specs(cls).items():
        flag = option_name(name, renamed)
        kind = _option_type(hints[name], spec)
        decl = f"{flag}/--no-{flag[2:]}" if kind is bool else flag
        option = typer.Option(
            decl,
            help=help_text(field, spec, flag),
            show_default=False,  # the help says the class's default, not None
            rich_help_panel=(panels or {}).get(spec.group, spec.group.capitalize() or None),
        )
        out.append(
            inspect.Parameter(
                name,
                inspect.Parameter.KEYWORD_ONLY,
                default=None,
                annotation=Annotated[kind | None, option],
            )
        )
    return out


def with_options(command: Callable, options: list[inspect.Parameter]) -> Callable:
    """Give ``command`` (which takes ``**fields``) the ``options`` before its own.

    The options are appended to the command's signature (``__signature__``, which typer
    reads) and reach it in ``**fields`` by their names; its own parameters keep theirs.
    """
    own = [
        p.replace(kind=inspect.Parameter.KEYWORD_ONLY)
        for p in inspect.signature(command, eval_str=True).parameters.values()
        if p.kind is not inspect.Parameter.VAR_KEYWORD
    ]
    clash = {p.name for p in own} & {p.name for p in options}
    if clash:
        raise TypeError(f"{command.__name__}: options named twice: {', '.join(sorted(clash))}")
    command.__signature__ = inspect.Signature([*options, *own])
    return command


class PanelledCommand(TyperCommand):
    """A command whose ``--help`` rich draws with its options in panels
    (``rich_help_panel``), whatever the markup mode of the app.

    Help texts are plain text: they are escaped here, so that rich shows the brackets of
    ``[m; default 0.05]`` instead of reading them as markup tags, and the paragraphs of
    the command's docstring are wrapped to the terminal's width.
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.rich_markup_mode = "rich"
        if self.help:  # (rich keeps the line breaks of a docstring's later paragraphs)
            paragraphs = inspect.cleandoc(self.help).split("\n\n")
            self.help = escape("\n\n".join(" ".join(par.split()) for par in paragraphs))
        for param in self.params:
            if getattr(param, "help", None):
                param.help = escape(param.help)

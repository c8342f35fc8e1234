"""Every option's unit and default in brackets reaches ``--help`` (no markup eats them).

A command drawn by rich (``chain``: its options in panels) holds its help texts as rich
markup, with the brackets escaped: what it must show is that markup's plain text.
"""

from __future__ import annotations

import re

import pytest
import typer
from rich.text import Text
from typer.testing import CliRunner

from dominowave.cli import app

COMMAND = typer.main.get_command(app)
BRACKETED = re.compile(r"\[[^\]]+\]")


def _commands():
    return sorted(COMMAND.commands.items())


@pytest.mark.parametrize(("name", "command"), _commands(), ids=[n for n, _ in _commands()])
def test_every_bracketed_unit_of_an_option_is_shown(name, command):
    result = CliRunner().invoke(app, [name, "--help"], env={"COLUMNS": "80"})
    assert result.exit_code == 0, result.output
    # the help wraps at 80 columns (inside the frames of rich's panels)
    shown = " ".join(re.sub("[│╭╮╰╯─]", " ", result.output).split())
    rich = getattr(command, "rich_markup_mode", None) == "rich"
    checked = 0
    for param in command.params:
        text = getattr(param, "help", None) or ""
        for unit in BRACKETED.findall(Text.from_markup(text).plain if rich else text):
            assert " ".join(unit.split()) in shown, f"{name} {param.opts[0]}: {unit} not shown"
            checked += 1
    if name in ("chain", "leaning"):
        assert checked >= 3, f"{name}: expected options with units"
    assert max(len(line) for line in result.output.splitlines()) <= 80

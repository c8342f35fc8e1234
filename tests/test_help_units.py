"""Every option's unit and default in brackets reaches ``--help`` (no markup eats them)."""

from __future__ import annotations

import re

import pytest
import typer
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
    shown = " ".join(result.output.split())  # the help wraps at 80 columns
    checked = 0
    for param in command.params:
        for unit in BRACKETED.findall(getattr(param, "help", None) or ""):
            assert " ".join(unit.split()) in shown, f"{name} {param.opts[0]}: {unit} not shown"
            checked += 1
    if name in ("chain", "leaning"):
        assert checked >= 3, f"{name}: expected options with units"
    assert max(len(line) for line in result.output.splitlines()) <= 80

"""Fixtures shared by all test directories."""

import sys

import pytest

from dominowave.cli import main


@pytest.fixture
def cli(monkeypatch, capsys):
    """Run ``dominowave ARGS`` in this process: ``cli(*args) -> (exit code, stdout, stderr)``."""

    def run(*args) -> tuple[int, str, str]:
        monkeypatch.setattr(sys, "argv", ["dominowave", *map(str, args)])
        try:
            main()
            code = 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else 1
        out, err = capsys.readouterr()
        return code, out, err

    return run

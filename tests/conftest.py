"""Fixtures shared by all test directories, and the ``validate`` marker."""

import sys

import pytest

from dominowave.cli import main


def pytest_collection_modifyitems(items):
    """Mark every physics validation (``test_validate_*``): ``pytest -m validate`` runs
    them alone, ``-m "not validate"`` the rest."""
    for item in items:
        if item.originalname.startswith("test_validate"):
            item.add_marker(pytest.mark.validate)


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

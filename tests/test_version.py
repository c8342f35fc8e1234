"""`dominowave --version`: the installed version, and the commit of a git checkout."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import dominowave

ROOT = Path(__file__).parents[1]


def test_version_matches_the_project_metadata():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert dominowave.__version__ == project["version"]


def test_version_option_prints_version_and_commit(cli):
    code, stdout, _ = cli("--version")
    assert code == 0
    assert re.fullmatch(
        rf"dominowave {re.escape(dominowave.__version__)}( \(git [0-9a-f]{{40}}(-dirty)?\))?\n",
        stdout,
    )
    if (ROOT / ".git").exists():  # a checkout (CI clones one): the commit is named
        assert "(git " in stdout

"""What users read speaks of the package: no issue numbers, no document outside the
repository, no dated notes in the prose.

The provenance of a number is kept in one table per documentation page (number,
command, commit, date); the text refers to its row.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
USER_FILES = sorted(
    [
        *ROOT.glob("src/dominowave/**/*.py"),
        *ROOT.glob("docs/*.md"),
        *ROOT.glob("docs/**/*.py"),
        *ROOT.glob("benchmarks/**/*.py"),
        *ROOT.glob("benchmarks/*.md"),
        *ROOT.glob("examples/*.py"),
        *(p for p in ROOT.glob("tests/**/*.py") if p.name != Path(__file__).name),
        ROOT / "README.md",
    ]
)
# a development diary, or a document outside the repository
ISSUE = re.compile(
    r"\bissues? ?#?\d+\b|\(issue\b|\bsession \d+\b|DESIGN\.md|\.\./shared", re.IGNORECASE
)
# the package's own runs (a cited source's date is no diary)
DATE = re.compile(r"\b2026-\d\d-\d\d\b|\b\d{1,2} (Nov|Dec)\w* 2026\b")


@pytest.mark.parametrize("path", USER_FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_issue_or_session_numbers(path):
    found = [
        f"{i}: {line.strip()}"
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if ISSUE.search(line)
    ]
    assert not found, found


@pytest.mark.parametrize(
    "path", sorted(ROOT.glob("docs/*.md")), ids=lambda p: str(p.relative_to(ROOT))
)
def test_dates_only_in_the_provenance_table(path):
    """A date in a page's prose is a development diary; its table row is provenance."""
    found = [
        f"{i}: {line.strip()}"
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if DATE.search(line) and not line.lstrip().startswith("|")
    ]
    assert not found, found

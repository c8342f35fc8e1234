"""The CSV writer of the scripts of this folder: one dict a row, its keys the header."""

from __future__ import annotations

import csv
from pathlib import Path


def write_rows(path: Path, rows: list[dict]) -> None:
    """Write ``rows`` (equal keys, in order) to ``path`` as CSV with a header."""
    with Path(path).open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

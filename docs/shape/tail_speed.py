"""The tail speed of an ensemble and the CSV output shared by the scripts of this folder.

The tail speed of a member that reached the end of its chain is its mean speed over the
last ``TAIL`` pitches, ``TAIL (d + s) / (t_{N-1} - t_{N-1-TAIL})`` [m/s]: unlike the
settled-region fit it is defined for every such member, also where a short chain does not
settle (docs/fig6.md).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

TAIL = 10
"""Pitches of the tail speed ``(x_{N-1} - x_{N-1-TAIL}) / (t_{N-1} - t_{N-1-TAIL})``."""


def tail_speeds(ens, pitch: float) -> np.ndarray:
    """Tail speeds [m/s] of the members of ``ens`` that reached the end, shape (n,)."""
    return np.array(
        [TAIL * pitch / (r.arrival[-1] - r.arrival[-1 - TAIL]) for r in ens.runs if r.reached_all]
    )


def mean_and_stderr(values: np.ndarray) -> tuple[float, float]:
    """Mean and standard error of ``values`` (NaN where undefined: none, or one value)."""
    mean = values.mean() if values.size else np.nan
    stderr = values.std(ddof=1) / np.sqrt(values.size) if values.size > 1 else np.nan
    return mean, stderr


def write_rows(path: Path, rows: list[dict]) -> None:
    """Write ``rows`` (dicts with the same keys) to the CSV file ``path``."""
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

"""The tables the theory commands print: one row a dict, columns as ``(key, title)``.

``dominowave theory`` and ``dominowave leaning`` give the same three formats: an aligned
text table under a note line, CSV, and JSON (where a non-finite number is a string, as
JSON has none).
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Sequence

__all__ = ["as_csv", "as_json", "as_table", "cell"]


def cell(value) -> str:
    """A value as printed in a text table: yes/NO, 6 significant digits, or the text."""
    if isinstance(value, bool):
        return "yes" if value else "NO"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def as_table(
    rows: list[dict], columns: Sequence[tuple[str, str]], note: str, free_last: bool = False
) -> str:
    """Right-aligned columns under their titles, below ``note``; with ``free_last`` the
    last column (free text) is not padded."""
    header = [title for _, title in columns]
    body = [[cell(row[key]) for key, _ in columns] for row in rows]
    aligned = len(header) - 1 if free_last else len(header)
    widths = [max(len(r[i]) for r in [header, *body]) for i in range(aligned)]
    lines = [
        "  ".join([*(c.rjust(w) for c, w in zip(r[:aligned], widths, strict=True)), *r[aligned:]])
        for r in [header, *body]
    ]
    return "\n".join([note, *lines])


def as_csv(rows: list[dict], columns: Sequence[tuple[str, str]], header: str = "key") -> str:
    """CSV with a header of the column keys (``header="key"``) or titles (``"title"``)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow([key if header == "key" else title for key, title in columns])
    writer.writerows([[row[key] for key, _ in columns] for row in rows])
    return buffer.getvalue().rstrip("\n")


def _json_value(value):
    # JSON has no infinity: non-finite numbers become the strings "inf" / "nan"
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    return value


def as_json(rows: list[dict]) -> str:
    """The rows as a JSON list of objects."""
    return json.dumps([{k: _json_value(v) for k, v in row.items()} for row in rows], indent=1)

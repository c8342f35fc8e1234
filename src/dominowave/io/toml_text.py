"""Reading and writing the small TOML subset that study files use.

Python 3.11 reads TOML with :mod:`tomllib` but cannot write it; resolved configs
are plain tables of numbers, strings, booleans and lists, so a short writer
suffices. ``line_of_key`` maps a dotted key back to its line in the file, so that
an error message can point at ``study.toml:7``.
"""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

__all__ = ["dumps", "line_of_key", "loads_file", "toml_value"]


def loads_file(path: Path) -> tuple[dict, str]:
    """Parse the TOML file ``path``; return ``(data, text)``.

    A UTF-8 byte-order mark (as some Windows editors write) is skipped; CRLF line
    ends are TOML. Raises ``ValueError`` (one line, with the file name) for a
    missing, unreadable or malformed file.
    """
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise ValueError(f"{path}: study file not found") from None
    except IsADirectoryError:
        raise ValueError(f"{path}: is a directory, expected a study file (.toml)") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read study file ({exc})") from None
    try:
        return tomllib.loads(text), text
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from None


def toml_value(value) -> str:
    """One value in TOML syntax (floats round-trip exactly through ``repr``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        escaped = value.replace("\\", "\\\\").replace('"', '\\"')
        return f'"{escaped}"'
    if isinstance(value, list | tuple):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):  # TOML has no null: a key not set is left out
        items = ", ".join(f"{_key(k)} = {toml_value(v)}" for k, v in value.items() if v is not None)
        return "{" + items + "}"
    raise TypeError(f"cannot write {type(value).__name__} to TOML")


def _key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else toml_value(key)


def dumps(data: dict, comments: dict[str, str] | None = None) -> str:
    """Write nested dicts as TOML: scalars first, then one ``[table]`` per sub-dict.

    ``comments`` maps a dotted key (``"scenario.height"``) to a comment written
    on the line above it; ``dominowave config --example`` documents fields this way.
    """
    comments = comments or {}
    lines: list[str] = []

    def table(prefix: str, mapping: dict) -> None:
        scalars = {k: v for k, v in mapping.items() if not isinstance(v, dict)}
        tables = {k: v for k, v in mapping.items() if isinstance(v, dict)}
        if prefix:
            if lines:
                lines.append("")
            if prefix in comments:
                lines.extend(f"# {c}" for c in comments[prefix].splitlines())
            if scalars or not tables:  # a table holding only sub-tables needs no header
                lines.append(f"[{prefix}]")
        for key, value in scalars.items():
            full = f"{prefix}.{key}" if prefix else key
            if full in comments:
                lines.extend(f"# {c}" for c in comments[full].splitlines())
            if value is None:
                lines.append(f"# {_key(key)} = (not set)")
            else:
                lines.append(f"{_key(key)} = {toml_value(value)}")
        for key, value in tables.items():
            table(f"{prefix}.{_key(key)}" if prefix else _key(key), value)

    table("", data)
    return "\n".join(lines) + "\n"


_HEADER = re.compile(r"^\s*\[+\s*([^\]]+?)\s*\]+")
_ASSIGN = re.compile(r"^\s*([A-Za-z0-9_\-\.\"' ]+?)\s*=")


def line_of_key(text: str, dotted: str) -> int | None:
    """Line number (1-based) where the key ``dotted`` (or its closest parent) is written.

    A best-effort scan of ``[table]`` headers and ``key =`` lines; ``None`` when
    the key is not in the text (e.g. a required key that is missing).
    """
    best, best_len = None, 0
    target = dotted.split(".")
    table: list[str] = []
    for number, line in enumerate(text.splitlines(), start=1):
        header = _HEADER.match(line)
        if header:
            table = [p.strip().strip("\"'") for p in header.group(1).split(".")]
            path = table
        else:
            assign = _ASSIGN.match(line)
            if not assign:
                continue
            path = table + [p.strip().strip("\"'") for p in assign.group(1).split(".")]
        if len(path) > best_len and target[: len(path)] == path:
            best, best_len = number, len(path)
    return best

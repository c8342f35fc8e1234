"""Checkpoint files: the full state of a long run, verified on load.

A checkpoint is one ``.npz`` holding the state arrays and a JSON header with the
run's config key, the step count and a SHA-256 of every array. It is written
atomically; on load a truncated, tampered or foreign file is refused with a
one-line ``ValueError`` instead of silently resuming from garbage.

A run's *history* -- arrays that only grow along their first axis, such as the
trajectory frames and contact events of a chain -- is stored once, not in every
checkpoint: each save appends only the rows that are new since the previous save,
as one more chunk file in ``<name>.history/`` beside the checkpoint, listed with its
checksum in the header. A save therefore costs the state the run must restore plus
what happened since the last save, and the history is on disk once. A chunk written
by a save that was killed before its header is simply not listed, and overwritten.
"""

from __future__ import annotations

import hashlib
import json
import zipfile
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from dominowave.io.atomic import atomic_path

__all__ = ["CHECKPOINT_FORMAT", "history_dir", "load_checkpoint", "save_checkpoint"]

CHECKPOINT_FORMAT = 2
"""Version of the file layout (2: history in chunk files); format 1 still loads."""

_READABLE_FORMATS = (1, 2)

_HEADER = "__header__"


def _digest(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def history_dir(path: str | Path) -> Path:
    """The folder of the history chunks of checkpoint ``path``."""
    path = Path(path)
    return path.with_name(path.stem + ".history")


def save_checkpoint(
    path: str | Path, state: dict[str, np.ndarray], meta: dict, history: Iterable[str] = ()
) -> None:
    """Write ``state`` (name -> array, bit-exact) and ``meta`` (JSON-ready) to ``path``.

    ``history`` names arrays of ``state`` that only grow along their first axis
    between the saves of one run (same ``meta["key"]``): only their new rows are
    written, as a chunk file in :func:`history_dir` (see the module docstring).
    """
    path = Path(path)
    arrays = {k: np.asarray(v) for k, v in state.items()}
    if _HEADER in arrays:
        raise ValueError(f"state may not contain an array named {_HEADER}")
    history = sorted(k for k in set(history) if k in arrays)
    chunks = _stored_chunks(path, meta.get("key"), history)
    stored = {k: sum(c["rows"][k] for c in chunks) for k in history}
    if any(stored[k] > len(arrays[k]) for k in history):  # not a continuation: start over
        chunks, stored = [], dict.fromkeys(history, 0)
    rows = {k: arrays[k][stored[k] :] for k in history}
    if any(len(v) for v in rows.values()):
        folder = history_dir(path)
        folder.mkdir(exist_ok=True)
        name = f"{len(chunks):06d}.npz"
        with atomic_path(folder / name) as tmp, open(tmp, "wb") as fh:
            np.savez(fh, **rows)
        chunks.append({"file": name, "rows": {k: len(v) for k, v in rows.items()}})
        chunks[-1]["sha256"] = _digest(rows)
    main = {k: v[:0] if k in rows else v for k, v in arrays.items()}
    header = dict(meta, format=CHECKPOINT_FORMAT, sha256=_digest(main), history=chunks)
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **main, **{_HEADER: np.array(json.dumps(header))})


def _stored_chunks(path: Path, key, history: list[str]) -> list[dict]:
    """The history chunks listed by the checkpoint at ``path`` if it is one of the same
    run with the same history arrays, else none (the history is then written anew)."""
    try:
        with np.load(path, allow_pickle=False) as data:
            header = json.loads(str(data[_HEADER]))
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError):
        return []
    chunks = header.get("history") or []
    if header.get("key") != key or any(sorted(c["rows"]) != history for c in chunks):
        return []
    return chunks


def load_checkpoint(path: str | Path, key: str | None = None) -> tuple[dict, dict]:
    """Read a checkpoint; return ``(state, meta)``.

    Raises ``ValueError`` if the file is missing, unreadable, corrupt (checksum), of
    another format, or -- when ``key`` is given -- of a run with another config.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"checkpoint {path} not found")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise ValueError(f"checkpoint {path} is corrupt or truncated ({exc})") from None
    try:
        header = json.loads(str(arrays.pop(_HEADER)))
    except (KeyError, ValueError):
        raise ValueError(f"checkpoint {path} is corrupt (no valid header)") from None
    if header.get("format") not in _READABLE_FORMATS:
        raise ValueError(
            f"checkpoint {path} has format {header.get('format')!r}, expected one of"
            f" {_READABLE_FORMATS}"
        )
    if header.get("sha256") != _digest(arrays):
        raise ValueError(f"checkpoint {path} is corrupt (checksum mismatch)")
    if key is not None and header.get("key") != key:
        raise ValueError(f"checkpoint {path} belongs to config {header.get('key')!r}, not {key!r}")
    pieces = {k: [v] for k, v in arrays.items()}
    for chunk in header.get("history") or []:
        for name, rows in _load_chunk(history_dir(path) / chunk["file"], chunk).items():
            pieces[name].append(rows)
    return {k: v[0] if len(v) == 1 else np.concatenate(v) for k, v in pieces.items()}, header


def _load_chunk(path: Path, chunk: dict) -> dict[str, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as data:
            rows = {k: data[k] for k in data.files}
    except FileNotFoundError:
        raise ValueError(f"checkpoint history chunk {path} is missing") from None
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise ValueError(f"checkpoint history chunk {path} is corrupt ({exc})") from None
    if _digest(rows) != chunk.get("sha256"):
        raise ValueError(f"checkpoint history chunk {path} is corrupt (checksum mismatch)")
    return rows

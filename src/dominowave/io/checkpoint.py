"""Checkpoint files: the full state of a long run, verified on load.

A checkpoint is one ``.npz`` holding the state arrays and a JSON header with the
run's config key, the step count and a SHA-256 of every array. It is written
atomically; on load a truncated, tampered or foreign file is refused with a
one-line ``ValueError`` instead of silently resuming from garbage.
"""

from __future__ import annotations

import hashlib
import json
import zipfile
from pathlib import Path

import numpy as np

from dominowave.io.atomic import atomic_path

__all__ = ["CHECKPOINT_FORMAT", "load_checkpoint", "save_checkpoint"]

CHECKPOINT_FORMAT = 1
"""Version of the file layout; bumped if it ever changes."""

_HEADER = "__header__"


def _digest(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def save_checkpoint(path: str | Path, state: dict[str, np.ndarray], meta: dict) -> None:
    """Write ``state`` (name -> array, bit-exact) and ``meta`` (JSON-ready) to ``path``."""
    arrays = {k: np.asarray(v) for k, v in state.items()}
    if _HEADER in arrays:
        raise ValueError(f"state may not contain an array named {_HEADER}")
    header = dict(meta, format=CHECKPOINT_FORMAT, sha256=_digest(arrays))
    with atomic_path(Path(path)) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays, **{_HEADER: np.array(json.dumps(header))})


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
    if header.get("format") != CHECKPOINT_FORMAT:
        raise ValueError(
            f"checkpoint {path} has format {header.get('format')!r}, expected {CHECKPOINT_FORMAT}"
        )
    if header.get("sha256") != _digest(arrays):
        raise ValueError(f"checkpoint {path} is corrupt (checksum mismatch)")
    if key is not None and header.get("key") != key:
        raise ValueError(f"checkpoint {path} belongs to config {header.get('key')!r}, not {key!r}")
    return arrays, header

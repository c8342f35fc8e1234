"""The folder of a sweep: one result folder per point plus an index.

Layout::

    SWEEP/
      study.toml          the study that was run (resolved)
      index.json          every stored point: key, status, swept values, folder
      points/<key>/       one result folder per point (see dominowave.io.results)
      unreadable/<key>/   a point folder with a file that did not parse, set aside
      .lock               held (flock) by the sweep writing the folder

The point folders are the truth: each appears atomically and only once (the
first complete writer wins), and ``index.json`` is rebuilt from them, so a kill
at any moment loses at most the points still running.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import shutil
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from dominowave.io.atomic import TMP_PREFIX, ensure_writable_dir, write_json
from dominowave.io.results import result_status, unreadable_file

__all__ = ["LOCK_NAME", "SweepStore"]

LOCK_NAME = ".lock"
"""File in the sweep folder that the sweep writing it holds locked."""


@dataclass
class SweepStore:
    """Read and write the point folders and the index of one sweep folder."""

    root: Path

    def __post_init__(self):
        self.root = Path(self.root)

    @property
    def points_dir(self) -> Path:
        return self.root / "points"

    @property
    def index_path(self) -> Path:
        return self.root / "index.json"

    def open_for_writing(self) -> SweepStore:
        """Create the folders, check they are writable, remove half-written leftovers."""
        ensure_writable_dir(self.root)
        ensure_writable_dir(self.points_dir)
        for stale in self.points_dir.glob(TMP_PREFIX + "*"):
            shutil.rmtree(stale, ignore_errors=True) if stale.is_dir() else stale.unlink()
        return self

    @contextlib.contextmanager
    def lock(self) -> Iterator[None]:
        """Hold the folder's write lock; ``ValueError`` if another sweep holds it.

        An advisory ``flock`` on ``SWEEP/.lock``: the kernel releases it when the
        holder exits, so a killed sweep never leaves the folder locked.
        """
        with open(self.root / LOCK_NAME, "a+", encoding="utf-8") as fh:
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                fh.seek(0)
                holder = fh.read().strip() or "unknown"
                raise ValueError(
                    f"sweep folder {self.root} is being written by another sweep (pid {holder});"
                    " wait for it to end, or choose another --out"
                ) from None
            fh.seek(0)
            fh.truncate()
            fh.write(f"{os.getpid()}\n")
            fh.flush()
            try:
                yield
            finally:
                fcntl.flock(fh, fcntl.LOCK_UN)

    def folder(self, key: str) -> Path:
        return self.points_dir / key

    @property
    def unreadable_dir(self) -> Path:
        return self.root / "unreadable"

    def status(self) -> dict[str, str]:
        """key -> "ok" | "failed" for every complete point folder."""
        if not self.points_dir.is_dir():
            return {}
        out = {}
        for folder in sorted(self.points_dir.iterdir()):
            if folder.name.startswith(TMP_PREFIX) or not folder.is_dir():
                continue
            status = result_status(folder)
            if status is not None:
                out[folder.name] = status
        return out

    def set_aside_unreadable(self) -> list[str]:
        """Move every point folder with a file that does not parse to ``unreadable/``.

        Such a point is not stored: the sweep runs it again. Its folder is kept (never
        deleted) as ``unreadable/<key>`` (``<key>.2``, ... if that exists). Returns one
        line per folder moved, naming it and the file that failed. Needs the write lock.
        """
        lines = []
        for key in self.status():
            why = unreadable_file(self.folder(key))
            if why is None:
                continue
            ensure_writable_dir(self.unreadable_dir)
            target, n = self.unreadable_dir / key, 1
            while target.exists():
                n += 1
                target = self.unreadable_dir / f"{key}.{n}"
            os.replace(self.folder(key), target)
            lines.append(f"point {key}: {why}; set aside as {target}, it runs again")
        return lines

    def write_index(self, overrides: dict[str, dict]) -> dict:
        """Rebuild index.json from the point folders; ``overrides`` maps key -> swept values.

        Points stored by earlier studies in the same folder keep their entry.
        """
        old = self.read_index().get("points", {}) if self.index_path.is_file() else {}
        points = {}
        for key, status in self.status().items():
            swept = overrides.get(key, old.get(key, {}).get("swept", {}))
            points[key] = {"status": status, "swept": swept, "folder": f"points/{key}"}
        index = {"n_points": len(points), "points": points}
        write_json(self.index_path, index)
        return index

    def read_index(self) -> dict:
        """index.json as a dict (ValueError if missing or corrupt)."""
        try:
            return json.loads(self.index_path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ValueError(f"{self.root}: not a sweep folder (no index.json)") from None
        except (OSError, json.JSONDecodeError) as exc:
            raise ValueError(f"{self.index_path}: unreadable ({exc})") from None

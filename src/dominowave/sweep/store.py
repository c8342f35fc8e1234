"""The folder of a sweep: one result folder per point plus an index.

Layout::

    SWEEP/
      study.toml          the study that was run (resolved)
      index.json          every stored point: key, status, swept values, folder
      points/<key>/       one result folder per point (see dominowave.io.results)

The point folders are the truth: each appears atomically and only once (the
first complete writer wins), and ``index.json`` is rebuilt from them, so a kill
at any moment loses at most the points still running.
"""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from pathlib import Path

from dominowave.io.atomic import TMP_PREFIX, ensure_writable_dir, write_json
from dominowave.io.results import result_status

__all__ = ["SweepStore"]


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

    def folder(self, key: str) -> Path:
        return self.points_dir / key

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

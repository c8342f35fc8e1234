"""Provenance of a run: what produced these numbers, where, when, how fast."""

from __future__ import annotations

import functools
import getpass
import importlib.metadata
import os
import platform
import socket
import subprocess
import sys
from datetime import UTC, datetime
from pathlib import Path

import dominowave

__all__ = ["git_commit", "provenance"]


def _version(dist: str) -> str | None:
    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return None


@functools.cache
def git_commit() -> str | None:
    """Commit of the source tree the package is imported from (None outside git)."""
    src = Path(dominowave.__file__).resolve().parent
    try:
        out = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=src, capture_output=True, text=True, timeout=5
        )
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=src,
            capture_output=True,
            text=True,
            timeout=5,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    if out.returncode != 0:
        return None
    return out.stdout.strip() + ("-dirty" if dirty.stdout.strip() else "")


def provenance(*, key: str, seed: int | None, wall_time: float, started: float) -> dict:
    """Everything needed to reproduce a run (JSON-ready).

    ``wall_time`` [s] is the time the scenario took, ``started`` its POSIX start time.
    """
    try:
        user = getpass.getuser()
    except (KeyError, OSError):
        user = None
    return {
        "key": key,
        "package": "dominowave",
        "version": dominowave.__version__,
        "git_commit": git_commit(),
        "numpy": _version("numpy"),
        "numba": _version("numba"),
        "scipy": _version("scipy"),
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "machine": socket.gethostname(),
        "cpu_count": os.cpu_count(),
        "user": user,
        "seed": seed,
        "started_utc": datetime.fromtimestamp(started, UTC).isoformat(timespec="seconds"),
        "wall_time_s": wall_time,
    }

"""Atomic file and folder writes: a killed process never leaves a half-written result.

Every result file is written to a temporary file in the same folder and moved
into place with :func:`os.replace`, which is atomic on POSIX file systems: a
reader sees the old file or the new one, never a mixture. Whole result folders
are built under a temporary name and renamed into place the same way.

Files are not fsync'ed: that protects against killed processes (the kernel keeps
what was written before the kill), not against a power failure in the seconds
before it; an fsync per file (about 4 ms here) would make the sweep client the
bottleneck.
"""

from __future__ import annotations

import contextlib
import errno
import json
import math
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

__all__ = [
    "TMP_PREFIX",
    "atomic_dir",
    "atomic_path",
    "disk_full_said",
    "ensure_writable_dir",
    "os_error_line",
    "remove_empty_created",
    "write_json",
    "write_text",
]

TMP_PREFIX = ".tmp-"
"""Name prefix of files and folders still being written (removed on resume)."""


@contextlib.contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success move it onto ``path``.

    On an exception the temporary file is removed and ``path`` is untouched.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(
        prefix=TMP_PREFIX + path.name + ".", suffix=path.suffix, dir=path.parent
    )
    os.close(fd)
    tmp = Path(tmp)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; results are shared files
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def write_json(path: Path, data) -> None:
    """Write ``data`` as indented, strict JSON (RFC 8259) to ``path`` atomically.

    JSON has no NaN or infinity: a non-finite float is written as ``null``, so
    that every JSON reader (not only Python's lenient one) can read the file.
    """
    text = json.dumps(_strict(data), indent=2, sort_keys=True, allow_nan=False)
    write_text(path, text + "\n")


def _strict(obj):
    """``obj`` with NumPy values as Python ones and non-finite floats as ``None``."""
    if isinstance(obj, dict):
        return {key: _strict(value) for key, value in obj.items()}
    if isinstance(obj, list | tuple):
        return [_strict(value) for value in obj]
    if hasattr(obj, "tolist"):  # NumPy scalar or array
        return _strict(obj.tolist())
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, Path):
        return str(obj)
    if obj is None or isinstance(obj, bool | int | str):
        return obj
    raise TypeError(f"cannot write {type(obj).__name__} to JSON")


def atomic_dir(final: Path, fill: Callable[[Path], None]) -> bool:
    """Build a folder with ``fill(tmp_dir)`` and rename it to ``final`` atomically.

    Returns ``False`` (and discards the new folder) if ``final`` already exists:
    the first complete writer wins, so a point is never stored twice.
    """
    final = Path(final)
    tmp = Path(tempfile.mkdtemp(prefix=TMP_PREFIX + final.name + ".", dir=final.parent))
    try:
        os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp makes 0700; results are shared folders
        with disk_full_said(final.parent):
            fill(tmp)
        try:
            os.rename(tmp, final)  # fails if final exists and is not empty
        except OSError:
            if final.exists():
                return False
            raise
        return True
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


LOW_DISK_BYTES = 16 * 2**20
"""Free space below which a failed write is taken for a full disk [bytes]."""


@contextlib.contextmanager
def disk_full_said(folder: Path) -> Iterator[None]:
    """Turn a write that failed on a full disk into ``OSError(ENOSPC)``.

    Libraries report a full disk in their own words (HDF5 behind netCDF says
    "NetCDF: HDF error"); if a write into ``folder`` fails and the disk has less than
    ``LOW_DISK_BYTES`` free, the error is re-raised as what it is.
    """
    try:
        yield
    except OSError as exc:
        if exc.errno in (errno.ENOSPC, errno.EDQUOT) or not _disk_is_full(folder):
            raise
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(folder)) from exc
    except Exception as exc:
        if not _disk_is_full(folder):
            raise
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(folder)) from exc


def os_error_line(exc: OSError) -> str:
    """One line for an operating-system error, saying "disk full" when it is that."""
    where = f" ({exc.filename})" if getattr(exc, "filename", None) else ""
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        return f"disk full{where}: free some space and re-run (finished results are kept)"
    return f"{exc.strerror or exc}{where}"


def _disk_is_full(folder: Path) -> bool:
    try:
        return shutil.disk_usage(folder).free < LOW_DISK_BYTES
    except OSError:
        return False


_CREATED: list[Path] = []
"""Folders :func:`ensure_writable_dir` created in this process (outermost first)."""


def ensure_writable_dir(path: Path) -> Path:
    """Create folder ``path`` if needed and check we can write into it.

    Raises ``ValueError`` naming the folder, instead of failing after a long run. The
    folders it creates are remembered, so that a command that then fails or is
    interrupted removes those it left empty (:func:`remove_empty_created`).
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"output folder {path} exists and is not a folder")
    missing = [p for p in (path, *path.parents) if not p.exists()]
    try:
        path.mkdir(parents=True, exist_ok=True)
        _CREATED.extend(reversed(missing))
        fd, probe = tempfile.mkstemp(prefix=TMP_PREFIX + "probe.", dir=path)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise ValueError(f"output folder {path} is not writable ({exc.strerror or exc})") from None
    return path


def remove_empty_created() -> list[Path]:
    """Remove the folders this process created that are still empty, innermost first
    (a refused or interrupted command leaves no empty output folder); returns them."""
    removed = []
    for folder in reversed(_CREATED):
        try:
            folder.rmdir()  # only an empty folder: nothing written is ever removed
            removed.append(folder)
        except OSError:
            pass
    _CREATED.clear()
    return removed

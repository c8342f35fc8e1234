"""numba's on-disk cache of the package's kernels, made stale by any change of the package.

The kernels are compiled with ``cache=True``: numba keeps the machine code of each
function on disk and loads it while the function's *own* source file is unchanged (its
content hash, or its modification time in older numba).  A compiled kernel also holds
the code of every function it calls, inlined or not, from other files: the DEM time loop
(``dem/engine.py``) contains the contact geometry (``dem/shapes``), the contact law
(``dem/point_law.py``) and the integrator.  With numba's own stamp an edit of the contact
law in an editable install would leave the cached time loop running the old law, with no
sign of it.  :func:`install` gives every cached function of the package a stamp that
includes a hash of all the package's source files, so that an edit of any of them
recompiles every kernel (once; ``dominowave`` says so before a run: cli/compiling.py).

It adds, before numba's own, a locator of each kind numba has (a user-given
``NUMBA_CACHE_DIR``, ``__pycache__`` beside the source, the user-wide cache directory)
restricted to the package's files, with the same cache paths and this stamp.  numba's
locators are internal API (``numba.core.caching``): where they are missing (another
numba), or where ``NUMBA_CACHE_LOCATOR_CLASSES`` chooses the locators, the package's
kernels keep numba's own stamp.  The stamp is taken once per process, at the first
kernel cache look-up: a file edited while a process runs is seen by the next process.
"""

from __future__ import annotations

import functools
import hashlib
from pathlib import Path

__all__ = ["install", "package_stamp"]

PACKAGE_DIR = Path(__file__).resolve().parent
"""The installed package: the folder of this module."""


@functools.cache
def package_stamp(package_dir: Path = PACKAGE_DIR) -> str:
    """SHA-256 (hex) of the relative path and the content of every ``.py`` file below
    ``package_dir``, in sorted order: changes with any edit, addition or removal."""
    digest = hashlib.sha256()
    for path in sorted(package_dir.rglob("*.py")):
        digest.update(path.relative_to(package_dir).as_posix().encode())
        digest.update(b"\0")
        digest.update(path.read_bytes())
        digest.update(b"\0")
    return digest.hexdigest()


def _stamped(locator: type, package_dir: Path) -> type:
    """numba's ``locator`` class, for the files below ``package_dir`` only, with the
    package's stamp beside the file's own."""

    class PackageLocator(locator):
        @classmethod
        def from_function(cls, py_func, py_file):
            try:
                inside = Path(py_file).resolve().is_relative_to(package_dir)
            except OSError:  # (a placeholder such as "<string>")
                inside = False
            return super().from_function(py_func, py_file) if inside else None

        def get_source_stamp(self):
            # (a folder of scripts calling the package's kernels: the package's stamp too)
            stamps = {package_stamp(package_dir), package_stamp(PACKAGE_DIR)}
            return (super().get_source_stamp(), *sorted(stamps))

    PackageLocator.__name__ = PackageLocator.__qualname__ = f"Package{locator.__name__}"
    return PackageLocator


def install(package_dir: Path = PACKAGE_DIR) -> bool:
    """Put the stamped locators of ``package_dir``'s files before numba's own (once per
    folder); call it before the package's kernels are defined.  Another folder (scripts
    with kernels of their own that call the package's, e.g. benchmarks/) gets the stamp
    of its own files and of the package.  Returns whether numba's locators were found."""
    try:
        from numba.core import caching
    except ImportError:  # pragma: no cover - numba is a dependency
        return False
    names = ("UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator")
    bases = [getattr(caching, n, None) or getattr(caching, f"_{n}", None) for n in names]
    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    if impl is None or any(b is None for b in bases):
        return False
    package_dir = Path(package_dir).resolve()
    marker = f"_dominowave_stamped_{package_dir}"
    if not getattr(impl, marker, False):
        impl._locator_classes = [_stamped(b, package_dir) for b in bases] + list(
            impl._locator_classes
        )
        setattr(impl, marker, True)
    return True

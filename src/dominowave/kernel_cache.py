"""numba's on-disk cache of the package's kernels, made stale by any change they can see.

The kernels are compiled with ``cache=True``: numba keeps the machine code of each
function on disk and loads it while the function's *own* source file is unchanged (its
content hash, or its modification time in older numba).  A compiled kernel also holds
the code of every function it calls, inlined or not, and the values of the globals it
reads, from other files: the DEM time loop (``dem/engine.py``) contains the contact
geometry (``dem/shapes``), the contact law (``dem/laws/point.py``) and the integrator.
With numba's own stamp an edit of the contact law in an editable install would leave the
cached time loop running the old law, with no sign of it.  :func:`install` gives every
cached function of the package a stamp that includes a hash of every source file its
kernel can reach (it recompiles once; ``dominowave`` says so before a run:
cli/compiling.py).

What a kernel can reach: the kernels live in the instruments ``dem/`` and ``rods/``,
which import nothing of the package but their own folder and the shared modules
``checks.py``, ``units.py``, this one and ``compile_ahead.py`` (tests/test_layers.py
holds them to it; the last compiles kernels and holds none, so it is not stamped).  So a kernel's
stamp hashes its own top-level folder and :data:`SHARED`; an edit of the command line,
the chain layer or the documentation recompiles nothing, an edit of ``dem/`` only the
DEM.  A kernel in a module at the package's top level, or outside the package, gets the
whole package's hash.

numba reads a cache index (its stamp and the signatures of the compiled versions) by
unpickling it whole before it compares the stamp, so an index whose signatures name a
type the package no longer has (a renamed state tuple) would stop the first run with an
``AttributeError`` instead of recompiling; :func:`install` makes numba treat such an
unreadable index of the package as stale (:func:`_tolerant_index`).

It adds, before numba's own, a locator of each kind numba has (a user-given
``NUMBA_CACHE_DIR``, ``__pycache__`` beside the source, the user-wide cache directory)
restricted to the package's files, with the same cache paths and this stamp.  numba's
locators are internal API (``numba.core.caching``): where they are missing (another
numba), or where ``NUMBA_CACHE_LOCATOR_CLASSES`` chooses the locators, the package's
kernels keep numba's own stamp.  The stamp is taken once per process, at the first
kernel cache look-up: a file edited while a process runs is seen by the next process.

:func:`kernels_cached` tells from numba's index whether a kernel's first call will load
it or compile it (the command line says so before a run; a scene's time loop is
compiled ahead in a second process if not: :mod:`dominowave.compile_ahead`).
"""

from __future__ import annotations

import functools
import hashlib
import pickle
from pathlib import Path

__all__ = ["SHARED", "install", "kernel_stamp", "kernels_cached", "package_stamp"]

PACKAGE_DIR = Path(__file__).resolve().parent
"""The installed package: the folder of this module."""
SHARED = ("checks.py", "units.py", "kernel_cache.py")
"""Top-level modules whose code a kernel may reach (this one also makes the stamp)."""


def _digest(package_dir: Path, paths) -> str:
    """SHA-256 (hex) of the relative path and the content of each file, in sorted order."""
    digest = hashlib.sha256()
    for path in sorted(paths):
        digest.update(path.relative_to(package_dir).as_posix().encode())
        digest.update(b"\0")
        digest.update(path.read_bytes())
        digest.update(b"\0")
    return digest.hexdigest()


@functools.cache
def package_stamp(package_dir: Path = PACKAGE_DIR) -> str:
    """Hash of every ``.py`` file below ``package_dir``: changes with any edit, addition or
    removal."""
    return _digest(package_dir, package_dir.rglob("*.py"))


@functools.cache
def kernel_stamp(top: str, package_dir: Path = PACKAGE_DIR) -> str:
    """Hash of what a kernel in the top-level folder ``top`` of ``package_dir`` can reach:
    every ``.py`` file of that folder and the :data:`SHARED` modules there are."""
    shared = [package_dir / name for name in SHARED if (package_dir / name).is_file()]
    return _digest(package_dir, [*(package_dir / top).rglob("*.py"), *shared])


def _reach_stamp(py_file: str, package_dir: Path) -> str:
    """The stamp of a kernel in ``py_file``: its instrument's, or the whole package's."""
    path = Path(py_file).resolve()
    if path.is_relative_to(package_dir):
        parts = path.relative_to(package_dir).parts
        if len(parts) > 1 and (package_dir / parts[0]).is_dir():
            return kernel_stamp(parts[0], package_dir)
    return package_stamp(package_dir)


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

        def get_cache_path(self):
            path = super().get_cache_path()
            _TOLERANT.add(Path(path).resolve())  # (its indexes may name removed types)
            return path

        def get_source_stamp(self):
            # (a folder of scripts calling the package's kernels: the package's stamp too)
            own = _reach_stamp(self._py_file, package_dir)
            stamps = {own} if package_dir == PACKAGE_DIR else {own, package_stamp(PACKAGE_DIR)}
            return (super().get_source_stamp(), *sorted(stamps))

    PackageLocator.__name__ = PackageLocator.__qualname__ = f"Package{locator.__name__}"
    return PackageLocator


_TOLERANT: set[Path] = set()
"""The cache folders of the stamped locators' kernels (in the source tree, or under a cache
directory): an index in one of them that cannot be read is stale (:func:`_tolerant_index`)."""


def _tolerant_index(cache_file: type) -> None:
    """Make ``cache_file`` (numba's ``IndexDataCacheFile``) read an index in a folder of
    :data:`_TOLERANT` that cannot be unpickled -- it names a class or module the package no
    longer has -- as an empty, stale one: numba then compiles and writes the index anew.
    Other indexes are read as numba reads them."""
    if getattr(cache_file, "_dominowave_tolerant", False):
        return
    load = cache_file._load_index

    def _load_index(self):
        try:
            return load(self)
        except (AttributeError, ImportError, EOFError, pickle.UnpicklingError):
            if Path(self._index_path).parent.resolve() in _TOLERANT:
                return {}
            raise

    cache_file._load_index = _load_index
    cache_file._dominowave_tolerant = True


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
    cache_file = getattr(caching, "IndexDataCacheFile", None)
    if cache_file is not None:
        _tolerant_index(cache_file)
    return True


def kernels_cached(dispatcher) -> bool:
    """Whether ``dispatcher`` (a ``numba.njit(cache=True)`` function) has a fresh
    on-disk cache, so its first call loads machine code instead of compiling.

    A function that numba builds anew for each value it closes over (the DEM time loop
    of each kind of scene) shares one index with its siblings: its own entries are those
    whose key ends with the hashes of its code and of its closure values (numba's
    ``Cache._index_key``)."""
    if dispatcher.signatures:  # compiled (or loaded) in this process already
        return True
    cache = getattr(dispatcher, "_cache", None)
    index = getattr(getattr(cache, "_cache_file", None), "_load_index", None)
    if index is None:  # not a cached dispatcher, or another numba's internals
        return False
    try:
        own = cache._index_key(None, dispatcher.targetctx.codegen())[-1]
        return any(key[-1] == own for key in index())
    except Exception:  # an unreadable index (of another package), or another numba's
        return False  # internals

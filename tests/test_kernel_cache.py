"""A cached kernel is compiled anew when any file of its package changes, not only its
own: an edited contact law must not run as the old one from numba's disk cache."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from dominowave import kernel_cache


def _package(root: Path, stamped: bool) -> None:
    """``mini``: a cached kernel in one file calling an inlined helper of another (as the
    DEM time loop calls the contact law), with or without the package stamp."""
    pkg = root / "mini"
    pkg.mkdir()
    install = "from dominowave.kernel_cache import install\ninstall(Path(__file__).parent)\n"
    (pkg / "__init__.py").write_text("from pathlib import Path\n" + (install if stamped else ""))
    (pkg / "law.py").write_text(
        "from numba import njit\n\n@njit(inline='always')\ndef force(x):\n    return 1.0 * x\n"
    )
    (pkg / "loop.py").write_text(
        textwrap.dedent(
            """\
            from numba import njit
            from mini.law import force

            @njit(cache=True)
            def run(x):
                return force(x)
            """
        )
    )


def _run(root: Path, module: str = "mini.loop") -> tuple[float, bool]:
    """``run(2.0)`` of ``module`` in a fresh process, and whether its kernel came from the
    disk cache (numba's count of cache hits)."""
    code = f"from {module} import run; print(run(2.0), sum(run.stats.cache_hits.values()))"
    value, hits = _python(root, code).split()
    return float(value), int(hits) > 0


@pytest.mark.parametrize("stamped", [True, False])
def test_an_edited_callee_recompiles_the_cached_kernel(tmp_path, stamped):
    """With the package stamp the edited law runs (4.0, compiled anew); with numba's own
    stamp the cached kernel keeps the old law (2.0, from the cache) -- the failure this
    module prevents (numba checks only the kernel's own file)."""
    _package(tmp_path, stamped)
    assert _run(tmp_path) == (2.0, False)  # compiled, cached
    assert _run(tmp_path) == (2.0, True)  # loaded from the cache
    law = tmp_path / "mini" / "law.py"
    law.write_text(law.read_text().replace("1.0 * x", "2.0 * x"))
    assert _run(tmp_path) == ((4.0, False) if stamped else (2.0, True))


@pytest.mark.parametrize("cache_dir", [False, True])
@pytest.mark.parametrize("stamped", [True, False])
def test_an_index_naming_a_removed_type_is_stale(tmp_path, stamped, cache_dir):
    """A kernel whose argument is a named tuple of another file: once the tuple is renamed,
    numba's index of the cached kernel names a class that no longer exists.  numba
    unpickles the index before it compares the stamp and stops with an AttributeError;
    in a package that installs the stamp, the index is stale and the kernel compiles --
    beside the source (``__pycache__``) and in a cache directory (``NUMBA_CACHE_DIR``)."""
    _package(tmp_path, stamped)
    env = {"NUMBA_CACHE_DIR": str(tmp_path / "cache")} if cache_dir else {}
    state = tmp_path / "mini" / "state.py"
    state.write_text(
        "from collections import namedtuple\n\nOld = namedtuple('Old', ['x'])\n\n\n"
        "def make(x):\n    return Old(x)\n"
    )
    (tmp_path / "mini" / "apply.py").write_text(
        "from numba import njit\n\n@njit(cache=True)\ndef run(s):\n    return 2.0 * s.x\n"
    )
    code = "from mini.state import make; from mini.apply import run; r = run(make(1.0))"
    code += "; print(r, sum(run.stats.cache_hits.values()))"
    assert _python(tmp_path, code, env) == "2.0 0"  # compiled, cached
    assert _python(tmp_path, code, env) == "2.0 1"  # loaded from the cache
    assert (tmp_path / "cache").is_dir() == cache_dir
    state.write_text(state.read_text().replace("Old", "New"))
    if stamped:
        assert _python(tmp_path, code, env) == "2.0 0"  # compiled anew
    else:
        with pytest.raises(subprocess.CalledProcessError) as failed:
            _python(tmp_path, code, env)
        assert "AttributeError: Can't get attribute 'Old'" in failed.value.stderr


def _python(root: Path, code: str, env: dict[str, str] | None = None) -> str:
    """The last line ``code`` prints in a fresh process with ``root`` on the path (and the
    environment variables ``env``, no ``NUMBA_CACHE_DIR`` unless given); a failure raises
    CalledProcessError with the process's stderr."""
    base = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env = {**base, **(env or {}), "PYTHONPATH": os.pathsep.join([str(root), *sys.path])}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    if out.returncode:
        raise subprocess.CalledProcessError(out.returncode, "python", stderr=out.stderr)
    return out.stdout.strip().splitlines()[-1]


def test_package_stamp_follows_every_source_file(tmp_path):
    (tmp_path / "a.py").write_text("x = 1\n")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b.py").write_text("y = 2\n")
    first = kernel_cache.package_stamp(tmp_path)
    assert kernel_cache.package_stamp(tmp_path) == first
    kernel_cache.package_stamp.cache_clear()
    (tmp_path / "sub" / "b.py").write_text("y = 3\n")
    assert kernel_cache.package_stamp(tmp_path) != first


def test_the_package_kernels_carry_their_instruments_stamp():
    from dominowave.dem import engine
    from dominowave.rods import kernel

    loop = engine.time_loop(engine.SceneKind(planar=True, boxes=False))
    stamp = loop._cache._impl.locator.get_source_stamp()
    assert stamp[1:] == (kernel_cache.kernel_stamp("dem"),)
    rods = next(f for f in vars(kernel).values() if hasattr(f, "_cache") and f._cache)
    assert rods._cache._impl.locator.get_source_stamp()[1:] == (kernel_cache.kernel_stamp("rods"),)


def _instrument_package(root: Path) -> None:
    """``mini`` with its kernel in an instrument folder ``inst/`` that calls a helper of
    the same folder and a constant of the shared ``units.py``; ``cli.py`` beside them."""
    pkg = root / "mini"
    (pkg / "inst").mkdir(parents=True)
    install = "from pathlib import Path\nfrom dominowave.kernel_cache import install\n"
    (pkg / "__init__.py").write_text(install + "install(Path(__file__).parent)\n")
    (pkg / "units.py").write_text("SCALE = 1.0\n")
    (pkg / "cli.py").write_text("WORDS = 'help'\n")
    (pkg / "inst" / "__init__.py").write_text("")
    (pkg / "inst" / "law.py").write_text(
        "from numba import njit\nfrom mini.units import SCALE\n\n"
        "@njit(inline='always')\ndef force(x):\n    return SCALE * x\n"
    )
    (pkg / "inst" / "loop.py").write_text(
        "from numba import njit\nfrom mini.inst.law import force\n\n"
        "@njit(cache=True)\ndef run(x):\n    return force(x)\n"
    )


def test_only_an_edit_a_kernel_can_see_recompiles_it(tmp_path):
    """An edit outside the kernel's instrument and the shared modules keeps the cached
    kernel; an edit of its folder or of the shared modules compiles it anew and runs."""
    _instrument_package(tmp_path)
    pkg = tmp_path / "mini"
    assert _run(tmp_path, "mini.inst.loop") == (2.0, False)
    (pkg / "cli.py").write_text("WORDS = 'more help'\n")
    assert _run(tmp_path, "mini.inst.loop") == (2.0, True)  # the command line is not in the kernel
    (pkg / "units.py").write_text("SCALE = 3.0\n")
    assert _run(tmp_path, "mini.inst.loop") == (6.0, False)  # a shared constant is
    (pkg / "inst" / "law.py").write_text(
        (pkg / "inst" / "law.py").read_text().replace("SCALE * x", "SCALE * x + 1.0")
    )
    assert _run(tmp_path, "mini.inst.loop") == (7.0, False)  # and its own folder

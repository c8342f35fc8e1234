"""A command that is about to compile the numba kernels says so."""

from __future__ import annotations

import importlib
import sys

from typer.testing import CliRunner

from dominowave.cli import app, compiling


def test_kernels_cached_reads_numbas_own_index(tmp_path, monkeypatch):
    """A fresh ``njit(cache=True)`` function has no cache until its first call has
    compiled it; a re-imported copy then finds its cache fresh."""
    (tmp_path / "fresh_kernel.py").write_text(
        "from numba import njit\n\n@njit(cache=True)\ndef twice(x):\n    return 2 * x\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("fresh_kernel")
    assert not compiling.kernels_cached(module.twice)
    assert module.twice(3) == 6
    assert compiling.kernels_cached(module.twice)  # compiled in this process
    del sys.modules["fresh_kernel"]
    again = importlib.import_module("fresh_kernel")
    assert not again.twice.signatures and compiling.kernels_cached(again.twice)


def test_chain_says_it_is_compiling_when_the_cache_is_missing(monkeypatch):
    monkeypatch.setattr(compiling, "kernels_cached", lambda dispatcher: False)
    result = CliRunner().invoke(app, ["chain", "--n", "4"])
    assert result.exit_code == 0, result.output
    assert result.output.startswith("compiling the DEM kernels (first run")
    assert "s (including compiling the kernels)" in result.output


def test_no_notice_when_the_kernels_are_cached(monkeypatch):
    monkeypatch.setattr(compiling, "kernels_cached", lambda dispatcher: True)
    result = CliRunner().invoke(app, ["rods", "--n", "4", "--rows", "1"])
    assert result.exit_code == 0, result.output
    assert "compiling" not in result.output
    assert not compiling.notice_if_compiling()  # the theory compiles nothing


def test_the_notice_says_how_long_and_a_terminal_hears_it_is_still_working(monkeypatch, capsys):
    """The notice gives the measured first-run time; on a terminal a line every
    HEARTBEAT_S seconds follows until the kernel has a compiled signature."""
    import sys
    import time

    class Kernel:  # a dispatcher whose compilation ends after 2.5 s
        end = time.monotonic() + 2.5

        @property
        def signatures(self):
            return ["f8()"] if time.monotonic() > self.end else []

    monkeypatch.setattr(compiling, "kernels_cached", lambda dispatcher: False)
    monkeypatch.setattr(compiling, "HEARTBEAT_S", 1.0)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    monkeypatch.setattr(
        compiling.importlib,
        "import_module",
        lambda name: type("M", (), {"run_loop": Kernel(), "advance": Kernel()}),
    )
    assert compiling.notice_if_compiling("dem")
    time.sleep(4.0)
    err = capsys.readouterr().err
    assert "about 4 minutes for the DEM on 2 cores" in err
    assert err.count("still compiling") == 2  # at 1 s and 2 s, not after the end

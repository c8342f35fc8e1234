"""A command that is about to compile the numba kernels says so (issue 16)."""

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

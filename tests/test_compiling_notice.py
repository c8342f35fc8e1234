"""A command that is about to compile the numba kernels says so."""

from __future__ import annotations

import importlib
import sys
import types

import pytest
from typer.testing import CliRunner

from dominowave import kernel_cache
from dominowave.cli import app, compiling
from dominowave.dem import SceneKind


def test_kernels_cached_reads_numbas_own_index(tmp_path, monkeypatch):
    """A fresh ``njit(cache=True)`` function has no cache until its first call has
    compiled it; a re-imported copy then finds its cache fresh."""
    (tmp_path / "fresh_kernel.py").write_text(
        "from numba import njit\n\n@njit(cache=True)\ndef twice(x):\n    return 2 * x\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("fresh_kernel")
    assert not kernel_cache.kernels_cached(module.twice)
    assert module.twice(3) == 6
    assert kernel_cache.kernels_cached(module.twice)  # compiled in this process
    del sys.modules["fresh_kernel"]
    again = importlib.import_module("fresh_kernel")
    assert not again.twice.signatures and kernel_cache.kernels_cached(again.twice)


def test_kernels_cached_tells_the_kinds_of_one_compiled_loop_apart(tmp_path, monkeypatch):
    """A loop compiled for each value it closes over (as dem.engine.time_loop) shares one
    index with its siblings: the kind compiled is cached, the other is not."""
    (tmp_path / "kinds_kernel.py").write_text(
        "import functools\nfrom numba import njit\n\n@functools.cache\ndef loop(FLAG):\n"
        "    @njit(cache=True)\n    def run(x):\n        if FLAG:\n            return 2 * x\n"
        "        return 3 * x\n    return run\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("kinds_kernel")
    assert module.loop(True)(2) == 4
    del sys.modules["kinds_kernel"]
    again = importlib.import_module("kinds_kernel")
    assert kernel_cache.kernels_cached(again.loop(True))
    assert not kernel_cache.kernels_cached(again.loop(False))


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
    monkeypatch.setattr(compiling, "_kernel", lambda need: ("DEM clumps", Kernel()))
    assert compiling.notice_if_compiling(SceneKind(planar=True, boxes=False))
    time.sleep(4.0)
    err = capsys.readouterr().err
    assert f"{compiling.FIRST_RUN['DEM clumps']} for the DEM clumps on 2 cores" in err
    assert err.count("still compiling") == 2  # at 1 s and 2 s, not after the end


@pytest.mark.parametrize(
    ("by_workers", "first_words", "heartbeats"),
    [(False, "compiling", 1), (True, "the workers compile", 0)],
)
def test_the_heartbeat_waits_only_on_kernels_this_process_compiles(
    by_workers, first_words, heartbeats, monkeypatch, capsys
):
    """On a terminal, kernels that this process compiles get the heartbeat after the
    notice. Kernels that the Dask workers of a sweep compile never get a signature in
    this process: their notice says once who compiles them, with the time, and starts
    no heartbeat (which would say "still compiling" until the command ends)."""
    started = []

    class Thread:  # records the heartbeat instead of starting it
        def __init__(self, target, args, daemon):
            self.target = target

        def start(self):
            started.append(self.target)

    monkeypatch.setattr(compiling, "kernels_cached", lambda dispatcher: False)
    monkeypatch.setattr(compiling, "threading", types.SimpleNamespace(Thread=Thread))
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert compiling.notice_if_compiling("rods", by_workers=by_workers)
    err = capsys.readouterr().err
    assert err.startswith(f"{first_words} the rods kernels (first run")
    assert f"{compiling.FIRST_RUN['rods']} for the rods on 2 cores" in err
    assert started == [compiling._heartbeat] * heartbeats


class Stop(Exception):
    """Raised where a command would start its sweep: the notice is all a test needs."""


def _stop(*args, **kwargs):
    raise Stop


@pytest.mark.parametrize(
    ("command", "runner"),
    [
        (["paper-fig6", "--quick"], "dominowave.sweep.fig6.run_fig6"),
        (["predict", "--gap", "0.012", "--floor", "felt"], "dominowave.sweep.predict.predict"),
        (["compare-rods", "--quick"], "dominowave.sweep.compare_rods.run_compare_rods"),
        (["sweep", "{study}"], "dominowave.sweep.runner.run_sweep"),
    ],
)
def test_the_commands_run_on_dask_workers_say_the_workers_compile(
    command, runner, tmp_path, monkeypatch
):
    """paper-fig6, predict, compare-rods and sweep run their kernels on Dask workers:
    their notice says that the workers compile them."""
    study = tmp_path / "study.toml"
    study.write_text(
        '[scenario]\nkind = "chain"\nn_dominoes = 4\n\n[sweep.grid]\nd_over_l = [0.3, 0.4]\n'
    )
    args = [word.format(study=study) for word in command]
    monkeypatch.setattr(compiling, "kernels_cached", lambda dispatcher: False)
    monkeypatch.setattr(runner, _stop)
    result = CliRunner().invoke(app, [*args, "--out", str(tmp_path / "out")])
    assert isinstance(result.exception, Stop), result.output
    assert result.output.startswith("the workers compile the ")


@pytest.mark.parametrize("shape", ["clump", "box"])
@pytest.mark.parametrize("model", ["2d", "3d"])
def test_the_notice_checks_the_loop_the_chain_runs(shape, model):
    """The kernels the chain command checks before it runs (chain.scenario.scene_kind,
    from the parameters) are those the built scene runs (Simulation.kind)."""
    from dominowave.chain import ChainParams, DominoChain, Push
    from dominowave.chain.scenario import scene_kind

    params = ChainParams(n_dominoes=3, shape=shape, model=model)
    sim, _ = DominoChain(params).build(Push(omega=12.0))
    sim.run(n_steps=1)
    assert sim.kind == scene_kind(params)

"""A second process compiles a kernel into the disk cache while the first compiles the
others (compile_ahead.py), as a DEM scene's time loop; the first loads it from there."""

from __future__ import annotations

import _thread
import importlib
import os
import subprocess
import sys
import threading

import numpy as np
import pytest
from numba.core import config

from dominowave import compile_ahead
from dominowave.dem import Material, Scene
from dominowave.dem.engine import time_loop
from dominowave.kernel_cache import kernels_cached

KERNELS = (
    "import functools\nfrom numba import njit\n\n@functools.cache\ndef loop(FLAG):\n"
    "    @njit(cache=True)\n    def run(x):\n        if FLAG:\n            return 2 * x\n"
    "        return 3 * x\n    return run\n"
)


@pytest.fixture
def fresh_kernels(tmp_path, monkeypatch):
    """A module of fresh cached kernels (one per value of FLAG) that this process and a
    second one can import, with two cores to run on."""
    name = f"ahead_kernels_{tmp_path.name}"
    (tmp_path / f"{name}.py").write_text(KERNELS)
    monkeypatch.syspath_prepend(str(tmp_path))
    path = os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")])
    monkeypatch.setenv("PYTHONPATH", path)
    monkeypatch.setattr(compile_ahead, "_cores", lambda: 2)
    return name


def test_the_second_process_compiles_the_kernel_and_the_first_call_loads_it(fresh_kernels):
    ahead = compile_ahead.start_compiling(fresh_kernels, "loop", (True,), (3,))
    assert ahead is not None
    assert ahead.wait()
    kernel = importlib.import_module(fresh_kernels).loop(True)
    assert not kernel.signatures and kernels_cached(kernel)  # in the cache, not compiled here
    assert kernel(3) == 6
    assert kernel.stats.cache_hits and not kernel.stats.cache_misses
    other = importlib.import_module(fresh_kernels).loop(False)
    assert not kernels_cached(other)  # the kind asked for, and no other
    assert compile_ahead.start_compiling(fresh_kernels, "loop", (True,), (3,)) is None


def test_one_second_process_per_kernel_at_a_time(fresh_kernels):
    first = compile_ahead.start_compiling(fresh_kernels, "loop", (False,), (3,))
    again = compile_ahead.start_compiling(fresh_kernels, "loop", (False,), (3,))
    assert again is first
    assert first.wait()


def test_no_second_process_where_it_cannot_pay(fresh_kernels, monkeypatch):
    kernel = importlib.import_module(fresh_kernels).loop(True)
    kernel(3)  # compiled here
    assert compile_ahead.start_compiling(fresh_kernels, "loop", (True,), (3,)) is None
    args = (fresh_kernels, "loop", (False,), (3,))
    monkeypatch.setattr(compile_ahead, "_cores", lambda: 1)
    assert compile_ahead.start_compiling(*args) is None
    monkeypatch.setattr(compile_ahead, "_cores", lambda: 2)
    monkeypatch.setattr(config, "DISABLE_JIT", True)
    assert compile_ahead.start_compiling(*args) is None


def test_a_failed_second_process_leaves_the_kernel_to_the_first(fresh_kernels):
    """Arguments the kernel cannot be typed for: the second process fails, nothing is
    cached, and the first compiles the kernel for its own call as it would without it."""
    ahead = compile_ahead.start_compiling(fresh_kernels, "loop", (True,), (None,))
    assert not ahead.wait()
    kernel = importlib.import_module(fresh_kernels).loop(True)
    assert not kernels_cached(kernel)
    assert kernel(3) == 6


def test_an_interrupt_while_waiting_stops_the_second_process():
    process = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    ahead = compile_ahead.Ahead(process)
    threading.Timer(0.5, _thread.interrupt_main).start()
    with pytest.raises(KeyboardInterrupt):
        ahead.wait()
    assert process.poll() is not None


def test_a_scene_asks_for_the_loop_its_first_run_calls(monkeypatch):
    """The kind and argument types given to the second process at build are those of the
    first run's call of the loop, or its work would be lost."""
    asked = []
    monkeypatch.setattr(compile_ahead, "start_compiling", lambda *task: asked.append(task))
    scene = Scene(gravity=(0.0, 0.0, -9.81))
    m = scene.add_material(Material(density=1000.0, kn=1e4, friction=0.3))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_sphere((0.0, 0.0, 0.011), 0.01, m)
    sim = scene.build(safety=0.1)
    ((module, factory, (kind,), args),) = asked
    sim.run(n_steps=3)
    assert getattr(importlib.import_module(module), factory) is time_loop
    assert kind == tuple(sim.kind)
    loop = time_loop(kind)
    assert tuple(loop.typeof_pyval(a) for a in args) in loop.signatures
    assert isinstance(args[9], np.ndarray) and args[9].shape == (5,)  # the stop array


def test_a_scene_of_boxes_compiles_its_loop_itself(monkeypatch):
    """Its set-up runs the loop (the first contact rows), so it could only wait."""
    asked = []
    monkeypatch.setattr(compile_ahead, "start_compiling", lambda *task: asked.append(task))
    scene = Scene(gravity=(0.0, 0.0, -9.81))
    m = scene.add_material(Material(density=1000.0, kn=1e4, friction=0.3))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_box((0.0, 0.0, 0.0251), (0.0025, 0.0125, 0.025), 0.00025, m)
    scene.build(safety=0.1)
    assert asked == []

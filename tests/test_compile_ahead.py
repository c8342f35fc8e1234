"""A second process compiles a kernel into the disk cache while the first compiles the
others (compile_ahead.py), as a DEM scene's time loop; the first loads it from there."""

from __future__ import annotations

import copy
import importlib
import pickle
import signal
import subprocess
import sys
import threading
import time

import numba
import pytest
from numba.core import config

from dominowave import compile_ahead
from dominowave.chain import ChainParams, DominoChain
from dominowave.dem import Material, Scene, engine, simulation
from dominowave.kernel_cache import kernels_cached

KERNELS = (
    "import functools\nfrom numba import njit\n\n@functools.cache\ndef loop(FLAG):\n"
    "    @njit(cache=True)\n    def run(x):\n        if FLAG:\n            return 2 * x\n"
    "        return 3 * x\n    return run\n"
)


@pytest.fixture
def fresh_kernels(tmp_path, monkeypatch):
    """A module of fresh cached kernels (one per value of FLAG) on this process's path,
    which the second process is given, with two cores to run on."""
    name = f"ahead_kernels_{tmp_path.name}"
    (tmp_path / f"{name}.py").write_text(KERNELS)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(compile_ahead, "_cores", lambda: 2)
    return name


def test_the_second_process_compiles_the_kernel_and_the_first_call_loads_it(fresh_kernels):
    task = compile_ahead.start_compiling(fresh_kernels, "loop", (True,), (3,))
    assert task is not None
    assert compile_ahead.wait(task)
    kernel = importlib.import_module(fresh_kernels).loop(True)
    assert not kernel.signatures and kernels_cached(kernel)  # in the cache, not compiled here
    assert kernel(3) == 6
    assert kernel.stats.cache_hits and not kernel.stats.cache_misses
    other = importlib.import_module(fresh_kernels).loop(False)
    assert not kernels_cached(other)  # the kind asked for, and no other
    assert compile_ahead.start_compiling(fresh_kernels, "loop", (True,), (3,)) is None


def test_one_second_process_per_task_at_a_time(fresh_kernels):
    first = compile_ahead.start_compiling(fresh_kernels, "loop", (False,), (3,))
    process = compile_ahead._RUNNING[first].process
    assert compile_ahead.start_compiling(fresh_kernels, "loop", (False,), (3,)) == first
    assert compile_ahead._RUNNING[first].process is process
    assert compile_ahead.wait(first)


def test_no_second_process_where_it_cannot_pay(fresh_kernels, monkeypatch):
    kernel = importlib.import_module(fresh_kernels).loop(True)
    kernel(3)  # compiled here
    assert compile_ahead.start_compiling(fresh_kernels, "loop", (True,), (3,)) is None
    args = (fresh_kernels, "loop", (False,), (3,))
    monkeypatch.setattr(compile_ahead, "_cores", lambda: 1)
    assert compile_ahead.start_compiling(*args) is None
    monkeypatch.setattr(compile_ahead, "_cores", lambda: 2)
    monkeypatch.setattr(compile_ahead.multiprocessing, "parent_process", lambda: object())
    assert compile_ahead.start_compiling(*args) is None  # a worker of another process
    monkeypatch.undo()
    monkeypatch.setattr(compile_ahead, "_cores", lambda: 2)
    monkeypatch.setattr(config, "DISABLE_JIT", True)
    assert compile_ahead.start_compiling(*args) is None
    monkeypatch.setattr(config, "DISABLE_JIT", False)
    monkeypatch.setattr(compile_ahead, "ENABLED", False)
    assert compile_ahead.start_compiling(*args) is None


def test_a_failed_second_process_leaves_the_kernel_to_the_first(fresh_kernels, monkeypatch):
    """Arguments the kernel cannot be typed for: the second process fails, nothing is
    cached, and the first compiles the kernel for its own call as it would without it.
    One that cannot start is no error either."""
    task = compile_ahead.start_compiling(fresh_kernels, "loop", (True,), (None,))
    assert not compile_ahead.wait(task)
    kernel = importlib.import_module(fresh_kernels).loop(True)
    assert not kernels_cached(kernel)
    assert kernel(3) == 6

    def cannot_start(*args, **kwargs):
        raise OSError("no more processes")

    monkeypatch.setattr(compile_ahead.subprocess, "Popen", cannot_start)
    assert compile_ahead.start_compiling(fresh_kernels, "loop", (False,), (3,)) is None


def test_an_interrupt_while_waiting_stops_the_second_process():
    process = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    task = compile_ahead.Task("a task", "never compiled", (), ())
    compile_ahead._RUNNING[task] = compile_ahead._Ahead(process)
    main = threading.main_thread().ident
    threading.Timer(0.5, signal.pthread_kill, (main, signal.SIGINT)).start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        compile_ahead.wait(task)
    assert process.returncode == -signal.SIGKILL
    assert time.monotonic() - started < 10


def test_the_second_process_ends_when_its_parent_is_killed():
    """Its parent killed (no exit handler runs), it does not compile on alone: it looks
    for its parent every PARENT_POLL_S (here a process that only does that and sleeps)."""
    watcher = (
        "import os, threading, time\nfrom dominowave import compile_ahead\n"
        "threading.Thread(target=compile_ahead._end_with, args=(os.getppid(),),"
        " daemon=True).start()\ntime.sleep(60)\n"
    )
    parent = subprocess.Popen(
        [sys.executable, "-c", "import subprocess, sys, time\n"
         f"child = subprocess.Popen([sys.executable, '-c', {watcher!r}])\n"
         "print(child.pid, flush=True)\ntime.sleep(60)\n"],
        stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    child = int(parent.stdout.readline())
    time.sleep(1.0)  # (its watch started)
    assert _alive(child)
    parent.kill()
    parent.wait()
    end = time.monotonic() + 10
    while time.monotonic() < end and _alive(child):
        time.sleep(0.1)
    assert not _alive(child)


def _alive(pid: int) -> bool:
    """Whether process ``pid`` runs (a zombie, ended but not yet reaped, does not)."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def _sphere_on_a_wall():
    scene = Scene(gravity=(0.0, 0.0, -9.81))
    m = scene.add_material(Material(density=1000.0, kn=1e4, friction=0.3))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_sphere((0.0, 0.0, 0.011), 0.01, m)
    return scene.build(safety=0.1)


def _clump_chain():
    chain = DominoChain(ChainParams(n_dominoes=4))
    sim, _ = chain.build(chain.resolve(None))
    return sim


@pytest.mark.parametrize("build", [_sphere_on_a_wall, _clump_chain])
@pytest.mark.parametrize("run", [{"n_steps": 3}, {"until": 0.01}])
def test_a_scene_asks_for_the_loop_its_first_run_calls(monkeypatch, build, run):
    """The kernel and argument types given to the second process at build are those of
    the first run's call of the loop (or its work would be lost), and they pickle (the
    second process's task) and copy (a simulation holds them)."""
    asked, called = [], []
    monkeypatch.setattr(compile_ahead, "start_compiling", lambda *task: asked.append(task))
    # the loop not run (and not compiled): its arguments only
    fake_loop = lambda *args: (called.append(args), (engine.DONE_STEPS, 0))[1]  # noqa: E731
    monkeypatch.setattr(simulation, "time_loop", lambda kind: (called.append(kind), fake_loop)[1])
    sim = build()
    ((module, factory, factory_args, args),) = asked
    sim.run(**run)
    kind, loop_args = called[:2]
    assert getattr(importlib.import_module(module), factory) is engine.time_loop
    assert factory_args == (tuple(kind),)
    types = tuple(numba.typeof(a) for a in args)
    assert types == tuple(numba.typeof(a) for a in loop_args)
    assert pickle.loads(pickle.dumps(types)) == types
    assert copy.deepcopy(types) == types


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


@pytest.mark.parametrize("planar_kernels", [True, False])
def test_a_first_run_of_another_kind_stops_the_second_process(monkeypatch, planar_kernels):
    """The planar kernels switched off after the build: the second process compiles a
    loop the run does not call, and the run stops it instead of waiting for it."""
    done = []
    task = lambda m, f, a, _: compile_ahead.Task(m, f, a, ())  # noqa: E731
    monkeypatch.setattr(compile_ahead, "start_compiling", task)
    monkeypatch.setattr(compile_ahead, "wait", lambda task: done.append("waited"))
    monkeypatch.setattr(compile_ahead, "stop", lambda task: done.append("stopped"))
    monkeypatch.setattr(simulation, "time_loop", lambda kind: lambda *a: (engine.DONE_STEPS, 0))
    sim = _clump_chain()  # (planar)
    sim.planar_kernels = planar_kernels
    sim.run(n_steps=3)
    sim.run(n_steps=3)
    assert done == (["waited"] if planar_kernels else ["stopped"])

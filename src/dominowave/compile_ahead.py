"""Compiling a kernel in a second process while this one compiles the others.

On the first run after an install (or an edit of the code a kernel reaches) numba
compiles the kernels one after the other, on one core, in one thread at a time.  Its
disk cache, though, is shared by processes.  A DEM scene first compiles the kernels that
its set-up calls from Python (the contact list, the energies, the pair properties), then
its time loop, the larger part: :func:`start_compiling` has a second process compile
the loop for the scene's argument types and write it to the cache meanwhile, and
:func:`wait`, before the loop's first call, waits for it (``dem.Simulation``).  The
call then loads the kernel from the cache, as every later run does: the machine code,
and so every trajectory, is the same.  On 2 cores the README's main job takes a tenth
to a quarter less time (benchmarks/README.md, "First run").

It is left out where it cannot pay: for a kernel compiled or cached already, with one
core, in a process that is itself another's worker (a Dask worker shares the cores with
its siblings), under ``NUMBA_DISABLE_JIT``, and where :data:`ENABLED` is off.  One second
process at a time compiles a kernel for given types.  It ends with the process that
started it: stopped at that one's exit or on an interrupt while waiting, and ending
itself when it finds its parent gone (killed).  A scene built and never run leaves it
compiling until then.  Should the second process fail, or fail to start, the first call
compiles the kernel itself, as without it.
"""

from __future__ import annotations

import atexit
import importlib
import multiprocessing
import os
import pickle
import subprocess
import sys
import threading
import time
from typing import NamedTuple

from numba.core import config

from dominowave.kernel_cache import kernels_cached

__all__ = ["Task", "start_compiling", "stop", "wait"]


class Task(NamedTuple):
    """A kernel to compile: ``module.factory(*factory_args)`` for the argument ``types``
    (numba types); picklable, as the second process is sent it."""

    module: str
    factory: str
    factory_args: tuple
    types: tuple


_RUNNING: dict[Task, _Ahead] = {}
"""The second processes started, by task."""
ENABLED = True
"""Whether :func:`start_compiling` may start a second process (off: every kernel is
compiled in the process that calls it, e.g. to time each compilation there)."""
PARENT_POLL_S = 0.5
"""How often [s] a second process looks whether its parent is still there."""


class _Ahead:
    """A second process compiling a kernel.  ``process``: its :class:`subprocess.Popen`."""

    def __init__(self, process: subprocess.Popen):
        self.process = process

    def wait(self) -> bool:
        """Wait until the kernel is compiled and in the cache; whether it is (the second
        process succeeded).  An interrupt while waiting stops the second process too."""
        try:
            return self.process.wait() == 0
        except BaseException:
            self.stop()
            raise

    def stop(self) -> None:
        """Stop the second process if it still runs."""
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()


def _cores() -> int:
    """The cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def start_compiling(module: str, factory: str, factory_args: tuple, args: tuple):
    """Start compiling the kernel ``module.factory(*factory_args)`` (a numba dispatcher
    with ``cache=True``; picklable ``factory_args``) for the types of ``args``, the
    arguments of its first call, in a second process.  Returns the :class:`Task` to
    :func:`wait` for (or :func:`stop`), or ``None`` where a second process cannot pay
    or could not start (module docstring)."""
    worker = multiprocessing.parent_process() is not None
    if not ENABLED or config.DISABLE_JIT or _cores() < 2 or worker:
        return None
    try:
        kernel = getattr(importlib.import_module(module), factory)(*factory_args)
        if kernels_cached(kernel):
            return None
        task = Task(module, factory, factory_args, tuple(kernel.typeof_pyval(a) for a in args))
        running = _RUNNING.get(task)
        if running is not None and running.process.poll() is None:
            return task
        message = pickle.dumps(task)
        process = subprocess.Popen(
            [sys.executable, "-m", __name__],
            stdin=subprocess.PIPE,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            # (this process's path: the package as it imported it, wherever from)
            env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        )
        with process.stdin:
            process.stdin.write(message)
    except Exception:  # (the first call compiles the kernel, as without a second process)
        return None
    _RUNNING[task] = _Ahead(process)
    return task


def wait(task: Task) -> bool:
    """Wait for the second process of ``task`` (of :func:`start_compiling`); whether it
    compiled the kernel into the cache."""
    ahead = _RUNNING.get(task)
    return ahead is not None and ahead.wait()


def stop(task: Task) -> None:
    """Stop the second process of ``task`` if it still runs (its kernel is not needed)."""
    ahead = _RUNNING.get(task)
    if ahead is not None:
        ahead.stop()


@atexit.register
def _stop_all() -> None:
    """At exit, stop the second processes still compiling: nothing will call their kernel."""
    for ahead in _RUNNING.values():
        ahead.stop()


def _end_with(parent: int) -> None:
    """End this process once ``parent`` is gone (a second process is reparented then)."""
    while os.getppid() == parent:
        time.sleep(PARENT_POLL_S)
    os._exit(1)


def _compile_task(parent: int) -> None:
    """The second process: compile, and so write to the cache, the kernel that
    :func:`start_compiling` named on its standard input, unless ``parent`` ends first."""
    threading.Thread(target=_end_with, args=(parent,), daemon=True).start()
    module, factory, factory_args, signature = pickle.load(sys.stdin.buffer)
    getattr(importlib.import_module(module), factory)(*factory_args).compile(signature)


if __name__ == "__main__":
    _compile_task(os.getppid())

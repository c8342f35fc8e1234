"""Where the first run's compiling goes: numba's compile time per function and module.

Runs one ``dominowave`` command in this process with numba's event API listening to
every compilation (``numba.core.event``, "numba:compile": only real compilations, not
loads from the cache), and prints each function's own (exclusive) and inclusive compile
time, then the exclusive times summed per module. Give it an empty cache to see a first
run:

    NUMBA_CACHE_DIR=$(mktemp -d) python benchmarks/compile_split.py chain --out DIR

(the arguments are those of ``dominowave``; the README's main job is ``chain``). Every
kernel is compiled in this process, the time loop too (``compile_ahead.ENABLED`` off: a
first run otherwise has a second process compile the loop, whose events this one does
not see).
"""

from __future__ import annotations

import collections
import sys
import time

from numba.core import event


class CompileTimes(event.Listener):
    """Exclusive and inclusive compile time [s] per function (a compilation includes
    those of the functions it calls, which this subtracts for the exclusive time)."""

    def __init__(self):
        self.stack: list[list] = []
        self.exclusive: collections.Counter = collections.Counter()
        self.inclusive: collections.Counter = collections.Counter()

    def on_start(self, ev):
        func = ev.data["dispatcher"].py_func
        self.stack.append([f"{func.__module__}.{func.__qualname__}", time.perf_counter(), 0.0])

    def on_end(self, ev):
        name, start, children = self.stack.pop()
        elapsed = time.perf_counter() - start
        self.inclusive[name] += elapsed
        self.exclusive[name] += elapsed - children
        if self.stack:
            self.stack[-1][2] += elapsed


def main() -> None:
    from typer.testing import CliRunner

    from dominowave import compile_ahead
    from dominowave.cli import app

    compile_ahead.ENABLED = False  # (every compilation in this process: module docstring)
    times = CompileTimes()
    event.register("numba:compile", times)
    start = time.perf_counter()
    result = CliRunner().invoke(app, sys.argv[1:])
    wall = time.perf_counter() - start
    print(f"dominowave {' '.join(sys.argv[1:])}: exit {result.exit_code}, wall {wall:.1f} s,"
          f" compiling {sum(times.exclusive.values()):.1f} s")  # fmt: skip
    print("| function | exclusive [s] | inclusive [s] |\n| --- | --- | --- |")
    for name, seconds in times.exclusive.most_common(15):
        print(f"| `{name}` | {seconds:.1f} | {times.inclusive[name]:.1f} |")
    modules: collections.Counter = collections.Counter()
    for name, seconds in times.exclusive.items():
        modules[name.split(".<locals>")[0].rsplit(".", 1)[0]] += seconds
    print("| module | exclusive [s] |\n| --- | --- |")
    for name, seconds in modules.most_common(10):
        print(f"| `{name}` | {seconds:.1f} |")


if __name__ == "__main__":
    main()

"""Say so when a command is about to compile the numba kernels, instead of a silent wait.

The kernels are compiled on their first call after installing the package or changing
the code they run (minutes on 2 cores, :data:`FIRST_RUN`; ``cache=True`` keeps the
machine code on disk), and loaded from that cache in a fraction of a second afterwards.
Whether a kernel's cache is fresh is read from numba's own index of it: an index that is
missing, of another numba version, or of another version of the source the kernel can
reach (its instrument's folder and the shared modules: :mod:`dominowave.kernel_cache`)
means a compilation.
"""

from __future__ import annotations

import importlib
import sys
import threading
import time

import typer

__all__ = [
    "FIRST_RUN",
    "KERNELS",
    "SCENARIO_KERNELS",
    "kernels_cached",
    "notice_if_compiling",
]

KERNELS: dict[str, tuple[str, str]] = {
    "dem": ("dominowave.dem.engine", "run_loop"),  # the DEM engine's compiled time loop
    "rods": ("dominowave.rods.kernel", "advance"),  # the rod model's time loop
}
"""The compiled entry point of each instrument (module, function): compiling it
compiles everything it calls."""

SCENARIO_KERNELS: dict[str, tuple[str, ...]] = {"chain": ("dem",), "rods": ("rods",)}
"""The kernels a study of each scenario kind runs (the theory runs none)."""

FIRST_RUN: dict[str, str] = {"dem": "about 4 minutes", "rods": "about 15 s"}
"""How long compiling takes on a 2-core machine with an empty cache (benchmarks/README.md:
the README's main job, 4 min 15 s of wall time; the rods example, 14 s)."""
HEARTBEAT_S = 30.0
"""Interval of the "still compiling" lines on a terminal [s]."""


def kernels_cached(dispatcher) -> bool:
    """Whether ``dispatcher`` (a ``numba.njit(cache=True)`` function) has a fresh
    on-disk cache, so its first call loads machine code instead of compiling."""
    if dispatcher.signatures:  # compiled (or loaded) in this process already
        return True
    cache = getattr(dispatcher, "_cache", None)
    index = getattr(getattr(cache, "_cache_file", None), "_load_index", None)
    if index is None:  # not a cached dispatcher, or another numba's internals
        return False
    try:
        return bool(index())
    except Exception:  # an unreadable index: numba recompiles and rewrites it
        return False


def notice_if_compiling(*instruments: str) -> bool:
    """Print one line on stderr if the kernels of ``instruments`` ("dem", "rods") will
    be compiled by this command; return whether it did."""
    missing, dispatchers = [], []
    for name in instruments:
        module, function = KERNELS[name]
        dispatcher = getattr(importlib.import_module(module), function)
        if not kernels_cached(dispatcher):
            missing.append(name.upper() if name == "dem" else name)
            dispatchers.append(dispatcher)
    if not missing:
        return False
    times = ", ".join(f"{FIRST_RUN[n.lower()]} for the {n}" for n in missing)
    typer.echo(
        f"compiling the {' and '.join(missing)} kernels (first run after installing or"
        f" changing them; {times} on 2 cores, once: later runs load them from the cache)",
        err=True,
    )
    if sys.stderr.isatty():  # on a terminal, say that it is still working
        threading.Thread(target=_heartbeat, args=(dispatchers,), daemon=True).start()
    return True


def _heartbeat(dispatchers) -> None:
    """Every :data:`HEARTBEAT_S`, one line on stderr until the kernels are compiled."""
    start = time.monotonic()
    while True:
        time.sleep(1.0)
        if all(d.signatures for d in dispatchers):
            return
        elapsed = time.monotonic() - start
        if elapsed // HEARTBEAT_S != (elapsed - 1.0) // HEARTBEAT_S:
            print(f"  still compiling ({elapsed:.0f} s)", file=sys.stderr, flush=True)

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

from dominowave.kernel_cache import kernels_cached

__all__ = [
    "FIRST_RUN",
    "notice_if_compiling",
    "study_kernels",
]

FIRST_RUN: dict[str, str] = {
    "DEM clumps": "20-50 s",
    "DEM boxes": "1-2 min",
    "rods": "about 15 s",
}
"""How long compiling takes on a 2-core machine with an empty cache, by kernel
(benchmarks/README.md, "First run": about 21 s for the main job, 49 s for the 3D clump
chain, about 45 s in a worker process, which compiles the loop itself; 45-111 s for the
box chains; 13 s for the rods): the DEM time loop of a scene of clumps or of boxes (each
compiles only its own kernels, dem.engine.time_loop), the rod model's."""
HEARTBEAT_S = 30.0
"""Interval of the "still compiling" lines on a terminal [s]."""


def _kernel(need):
    """``(name, dispatcher)`` of a kernel a command needs: ``"rods"`` (the rod model's
    time loop) or the :class:`~dominowave.dem.SceneKind` of a DEM scene (its time loop;
    compiling it compiles everything it calls)."""
    if need == "rods":
        return "rods", importlib.import_module("dominowave.rods.kernel").advance
    engine = importlib.import_module("dominowave.dem.engine")
    return ("DEM boxes" if need.boxes else "DEM clumps"), engine.time_loop(need)


def notice_if_compiling(*needs, by_workers: bool = False) -> bool:
    """Print one line on stderr if the kernels of ``needs`` (``"rods"``, or the
    :class:`~dominowave.dem.SceneKind` of a DEM scene) will be compiled by this command;
    return whether it did.

    ``by_workers``: the command runs its kernels in Dask worker processes (a sweep),
    which compile them; the line says so.  Otherwise this process compiles them, and on
    a terminal a line every :data:`HEARTBEAT_S` follows until it has.
    """
    missing = _uncached(needs)
    if not missing:
        return False
    times = ", ".join(f"{FIRST_RUN[name]} for the {name}" for name in missing)
    instruments = dict.fromkeys(name.split()[0] for name in missing)
    who = "the workers compile" if by_workers else "compiling"
    typer.echo(
        f"{who} the {' and '.join(instruments)} kernels (first run after installing or"
        f" changing them; {times} on 2 cores, once: later runs load them from the cache)",
        err=True,
    )
    # the heartbeat watches this process's dispatchers: the workers' compiling never
    # shows there, so for them it would say "still compiling" until the command ends
    if not by_workers and sys.stderr.isatty():
        dispatchers = [d for group in missing.values() for d in group]
        threading.Thread(target=_heartbeat, args=(dispatchers,), daemon=True).start()
    return True


def _uncached(needs) -> dict[str, list]:
    """The dispatchers of ``needs`` that have no fresh cache, by kernel name (a key of
    :data:`FIRST_RUN`)."""
    missing: dict[str, list] = {}
    for need in needs:
        name, dispatcher = _kernel(need)
        if not kernels_cached(dispatcher):
            missing.setdefault(name, []).append(dispatcher)
    return missing


def study_kernels(kind: str, points) -> list:
    """The kernels that the points of a study of scenario ``kind`` run (the needs of
    :func:`notice_if_compiling`): the rods' time loop, or the DEM time loop of each kind
    of scene among the points (whose ``params()`` give a chain's ``ChainParams``); the
    theory runs none."""
    if kind == "rods":
        return ["rods"]
    from dominowave.chain.build import ChainParams
    from dominowave.chain.scenario import scene_kind

    params = [p.params() for p in points if hasattr(p, "params")]
    return list(dict.fromkeys(scene_kind(p) for p in params if isinstance(p, ChainParams)))


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

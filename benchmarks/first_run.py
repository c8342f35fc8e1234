"""Time to the first result on an empty kernel cache, per kind of DEM scene.

Each command runs in a fresh process with its own empty ``NUMBA_CACHE_DIR``, so it
compiles every kernel it uses (and only those: ``dem.engine.time_loop`` compiles the
time loop of the scene's kind), then once more on the filled cache (loading only).
The difference of the two is the compiling. Run on an idle machine:

    python benchmarks/first_run.py [--repeat 1] [--only boxes] [--checkouts OLD NEW]

Commands: the README's main job (``dominowave chain``: a 2D clump chain), a 3D clump
chain, the 2D and 3D box chains (k/k* = 1e4), each with its default output; ``--only``
keeps those whose name contains the text.  ``--checkouts`` compares checkouts of the
repository (``PYTHONPATH`` to each one's ``src``) in interleaved runs, one after the
other for each repetition, as the machine's speed drifts by tens of per cent within an
hour.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

COMMANDS = {
    "README main job (2D clumps)": ["chain"],
    "3D clumps": ["chain", "--model", "3d", "--n", "10"],
    "2D boxes": ["chain", "--shape", "box", "--n", "10"],
    "3D boxes": ["chain", "--shape", "box", "--model", "3d", "--n", "10"],
}


def _wall(args: list[str], cache: str, out: str, src: str | None = None) -> float:
    env = {**os.environ, "NUMBA_CACHE_DIR": cache}
    if src is not None:  # (a checkout's package before the installed one)
        env["PYTHONPATH"] = src
    start = time.perf_counter()
    subprocess.run(
        [sys.executable, "-m", "dominowave", *args, "--out", out],
        env=env,
        check=True,
        capture_output=True,
    )
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1, help="runs per command (median)")
    parser.add_argument("--only", default="", help="the commands whose name contains this")
    parser.add_argument("--checkouts", nargs="*", default=[], help="repository checkouts")
    args = parser.parse_args()
    sources = {str(c): str(Path(c).resolve() / "src") for c in args.checkouts} or {"": None}
    where = "| checkout " if args.checkouts else ""
    print(f"| command {where}| empty cache [s] | filled cache [s] | compiling [s] |")
    print("| --- " * (5 if args.checkouts else 4) + "|")
    for name, command in COMMANDS.items():
        if args.only not in name:
            continue
        empty = {c: [] for c in sources}
        filled = {c: [] for c in sources}
        for _ in range(args.repeat):
            for checkout, src in sources.items():  # (interleaved)
                with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
                    empty[checkout].append(_wall(command, cache, str(Path(out) / "a"), src))
                    filled[checkout].append(_wall(command, cache, str(Path(out) / "b"), src))
        for checkout in sources:
            e, f = statistics.median(empty[checkout]), statistics.median(filled[checkout])
            runs = ", ".join(f"{x:.1f}" for x in empty[checkout])
            column = f"| {checkout} " if args.checkouts else ""
            print(
                f"| `dominowave {' '.join(command)}` ({name}) {column}| {e:.1f} ({runs}) "
                f"| {f:.1f} | {e - f:.1f} |"
            )


if __name__ == "__main__":
    main()

"""Time to the first result on an empty kernel cache, per kind of DEM scene.

Each command runs in a fresh process with its own empty ``NUMBA_CACHE_DIR``, so it
compiles every kernel it uses (and only those: ``dem.engine.time_loop`` compiles the
time loop of the scene's kind), then once more on the filled cache (loading only).
The difference of the two is the compiling. Run on an idle machine:

    python benchmarks/first_run.py [--repeat 1]

Commands: the README's main job (``dominowave chain``: a 2D clump chain), a 3D clump
chain, the 2D and 3D box chains (k/k* = 1e4), each with its default output.
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


def _wall(args: list[str], cache: str, out: str) -> float:
    env = {**os.environ, "NUMBA_CACHE_DIR": cache}
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
    args = parser.parse_args()
    print("| command | empty cache [s] | filled cache [s] | compiling [s] |")
    print("| --- | --- | --- | --- |")
    for name, command in COMMANDS.items():
        empty, filled = [], []
        for _ in range(args.repeat):
            with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
                empty.append(_wall(command, cache, str(Path(out) / "a")))
                filled.append(_wall(command, cache, str(Path(out) / "b")))
        e, f = statistics.median(empty), statistics.median(filled)
        print(f"| `dominowave {' '.join(command)}` ({name}) | {e:.1f} | {f:.1f} | {e - f:.1f} |")


if __name__ == "__main__":
    main()

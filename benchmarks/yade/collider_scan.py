"""YADE's collider settings on the identical chain: speed, collider runs, identical results.

bench_chain.py compares dominowave with YADE's fastest configuration of the same case.
This script re-measures the choice made in chain_yade.py: YADE 2023.02a's defaults
(``targetInterv=100, verletDist=-0.5``), a larger Verlet distance alone, and the setting
used (``targetInterv=0, verletDist=-1``), interleaved (A, B, C, C, B, A, ...) so that the
VM's drift cancels, engines only, one thread. For each: the median wall time, the number
of collider runs (``InsertionSortCollider.numAction``) and whether the final domino
positions are bitwise identical to those of the defaults (the collider settings must not
change the physics).

Run:  python benchmarks/yade/collider_scan.py [--rounds 3]
      (N = 30: the full run; N = 300: the first 40 000 steps; about 4 min)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))  # (bench_chain.py)
from bench_chain import case, steps_to_last_collision
from compare_yade import COLLIDERS, run_yade, scene_dict

SETTINGS = {
    "YADE defaults": COLLIDERS["defaults"],
    "verletDist -1": {"targetInterv": 100, "verletDist": -1},
    "chain_yade.py": COLLIDERS["targetInterv 0"],
}


def scan(n_dominoes: int, steps: int, rounds: int) -> None:
    chain = case(n_dominoes)
    scene = scene_dict(chain, chain.resolve(None), "engines", steps)
    names = list(SETTINGS)
    times = {name: [] for name in names}
    final, runs = {}, {}
    for k in range(rounds):
        for name in names if k % 2 == 0 else reversed(names):
            out = run_yade(dict(scene, collider=SETTINGS[name]))
            times[name].append(out["wall_time"])
            final[name] = np.array(out["final_positions"])
            runs[name] = out["collider_runs"]
    print(f"N = {n_dominoes}, {steps} steps, {rounds} interleaved rounds:")
    for name in names:
        same = bool(np.array_equal(final[name], final[names[0]]))
        print(
            f"  {name:14s} {SETTINGS[name]}: median {np.median(times[name]):.3f} s "
            f"({', '.join(f'{t:.3f}' for t in times[name])}), {runs[name]} collider runs, "
            f"final positions bitwise identical to the defaults: {same}",
            flush=True,
        )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    scan(30, steps_to_last_collision(case(30)), args.rounds)
    scan(300, 40_000, args.rounds)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

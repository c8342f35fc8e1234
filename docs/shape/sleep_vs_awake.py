"""Box chains whose resting dominoes sleep against the same chains with every domino awake.

A box domino that has come to rest is put to sleep (``DominoChain(sleep=True)``, the
default of box chains: every point slower than ``1e-3 sqrt(g l)`` for ``sqrt(l/g)``, with
the moving dominoes it touches; ``dem.Scene.build``'s ``sleep_speed``): it costs nothing
until a moving body touches or drives it. The criterion is not exact; this script
measures what it changes. For each chain it gives, asleep and awake: the front speed
fitted from domino 10 on, the largest relative difference of the arrival times (first
touch) of dominoes 1 .. N-1, the wall time of the run (warm kernels) and the dominoes
asleep at the end.

The chains: standard dominoes (``chain.presets.standard_domino``, felt floor, friction
0.3 between the dominoes and with the floor) at the 9.38 mm gap, 3D, at the default
fidelity (1 %), 30 to 300 dominoes; and the 2D chain of the paper's box dominoes (d/l =
0.4, k/k* = 1e4, friction 0.3 between the dominoes).

Run:  python docs/shape/sleep_vs_awake.py [--n 30,100,300] [--out sleep_vs_awake.csv]
"""

from __future__ import annotations

import argparse
import csv
import math
import time

import numpy as np

from dominowave.chain import ChainParams, DominoChain, Push
from dominowave.chain.presets import standard_domino
from dominowave.chain.wave import speed_from

FIT_FROM = 10


def chains(sizes: list[int]) -> dict[str, ChainParams]:
    """The chains measured, by name."""
    out = {}
    for n in sizes:
        out[f"standard 3D, {n}"] = standard_domino(
            gap=0.00938, floor="felt", n_dominoes=n, friction_dominoes=0.3, friction_floor=0.3
        )
    out["paper's box 2D, 30"] = ChainParams(shape="box", n_dominoes=30, friction_dominoes=0.3)
    return out


def run(p: ChainParams, sleep: bool) -> tuple[np.ndarray, float, float, int]:
    """(arrival times [s], front speed [m/s], wall time [s], dominoes asleep at the end)."""
    chain = DominoChain(p, sleep=sleep)
    start = time.perf_counter()
    stepper = chain.stepper(Push(omega=math.sqrt(p.g / p.height)))
    stepper.advance(np.iinfo(np.int64).max)
    result = stepper.result()
    wall = time.perf_counter() - start
    bodies = stepper.sim.bodies
    asleep = int(np.sum((bodies.held == 1) & np.isfinite(bodies.calm_since)))
    speed = speed_from(result.arrival, result.positions, FIT_FROM).speed
    return np.asarray(result.arrival), speed, wall, asleep


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", default="30,100,300", help="standard chains' lengths")
    parser.add_argument("--out", default="sleep_vs_awake.csv", help="CSV to write")
    args = parser.parse_args()
    run(standard_domino(gap=0.00938, floor="felt", n_dominoes=12), True)  # warm the kernels
    fields = ["chain", "speed_awake_m_s", "speed_asleep_m_s", "speed_change"]
    fields += ["largest_arrival_change", "wall_awake_s", "wall_asleep_s", "asleep_at_end"]
    with open(args.out, "w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(fields)
        for name, p in chains([int(n) for n in args.n.split(",")]).items():
            awake, v_awake, wall_awake, _ = run(p, False)
            asleep, v_asleep, wall_asleep, n_asleep = run(p, True)
            change = np.nanmax(np.abs(asleep[1:] - awake[1:]) / awake[1:])
            row = [name, f"{v_awake:.5f}", f"{v_asleep:.5f}", f"{v_asleep / v_awake - 1:+.2e}"]
            row += [f"{change:.2e}", f"{wall_awake:.3g}", f"{wall_asleep:.3g}", n_asleep]
            out.writerow(row)
            print(dict(zip(fields, row, strict=True)), flush=True)


if __name__ == "__main__":
    main()

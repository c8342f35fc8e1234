"""Box chains held until touched against the same chains with every box free.

A box stands in equilibrium on its flat base (it starts at the static overlap), so a
free untouched box stays at rest to round-off, and holding it until it is first touched
(``held=True``) is meant to change nothing. This script measures what it changes:

* the arrival times (first touch) of every domino of 12-domino chains, held and free:
  2D, 3D with yaw errors of 0.02 rad, 3D with shifts of 2 mm along and across the line;
* against that, how much the free chain's arrival times move when its push changes by
  one part in 1e12: the chain's own sensitivity to round-off;
* the velocity of domino 1 in the steps around its first touch, held and free (2D).

Run:  python docs/shape/held_vs_free.py [--out held_vs_free.csv]
"""

from __future__ import annotations

import argparse
import csv
import math

import numpy as np

from dominowave.chain import ChainParams, DominoChain, Push

COMMON = dict(n_dominoes=12, shape="box", friction_dominoes=0.3, friction_floor=0.5)
CASES = {
    "2d": dict(model="2d"),
    "3d, yaw 0.02 rad": dict(model="3d", lateral_asymmetry=0.02),
    "3d, shifts 2 mm": dict(model="3d", placement_along=0.002, placement_across=0.002),
}


PUSH_CHANGE = 1e-12  # (relative): a change at the level of round-off


def _push(p: ChainParams) -> Push:
    return Push(omega=1.2 * math.sqrt(p.g / p.height))


def arrivals(case: dict, held: bool, push_change: float = 0.0) -> np.ndarray:
    """First-touch times [s] of the dominoes of ``case`` (NaN: never touched), the push
    scaled by ``1 + push_change``."""
    p = ChainParams(held=held, **COMMON, **case)
    push = _push(p)
    chain = DominoChain(p, sleep=False)  # (a free domino at rest would fall asleep: held)
    return np.asarray(chain.run(Push(omega=push.omega * (1 + push_change))).arrival)


def release_steps(held: bool, steps: int = 6) -> list[tuple[float, float, float]]:
    """``(t, v_x, v_z)`` of domino 1 of the 2D chain in the steps around its first touch."""
    p = ChainParams(held=held, model="2d", **COMMON)
    sim, _ = DominoChain(p, sleep=False).build(_push(p))
    touch = arrivals(CASES["2d"], held=False)[1]
    sim.run(until=touch - 2 * sim.dt)
    rows = []
    for _ in range(steps):
        sim.run(n_steps=1)
        rows.append((sim.time, sim.bodies.vel[1, 0], sim.bodies.vel[1, 2]))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="held_vs_free.csv", help="CSV of the arrival times")
    args = parser.parse_args()
    with open(args.out, "w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(
            ["case", "domino", "arrival_free_s", "arrival_held_s", "relative_difference",
             "relative_change_push_1e-12"]
        )  # fmt: skip
        for name, case in CASES.items():
            free, held = arrivals(case, False)[1:], arrivals(case, True)[1:]
            nudged = arrivals(case, False, PUSH_CHANGE)[1:]
            rel = np.abs(held - free) / free  # (domino 0 is pushed at t = 0)
            sensitivity = np.abs(nudged - free) / free
            for n, row in enumerate(zip(free, held, rel, sensitivity, strict=True), start=1):
                out.writerow([name, n, *(f"{x:.9g}" for x in row)])
            print(
                f"{name}: held vs free, domino 2 {rel[1]:.2g}, largest {np.nanmax(rel):.2g};"
                f" push x (1 + 1e-12), largest {np.nanmax(sensitivity):.2g}"
            )
    print("domino 1 around its first touch (2D): t [s], free v_x v_z, held v_x v_z [m/s]")
    for (t, fx, fz), (_, hx, hz) in zip(release_steps(False), release_steps(True), strict=True):
        print(f"  {t:.6f}  {fx:+.3e} {fz:+.3e}   {hx:+.3e} {hz:+.3e}")


if __name__ == "__main__":
    main()

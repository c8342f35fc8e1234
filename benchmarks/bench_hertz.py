"""Cost of the Hertz normal law of box contacts against the linear law.

The same scenes run with ``Scene(normal_law="linear")`` (materials giving ``kn``) and
``Scene(normal_law="hertz")`` (materials giving ``young``), at the same time step: N boxes
resting on a floor (4 contact points each in 3D, 2 planar rows) and N two-box stacks
(x, y translations blocked: a box-box face contact of 4 points).  CPU time per step,
median of --repeat runs of --steps steps after a warm-up; the difference between the laws
divided by the contact rows is the extra cost of one Hertz point.

Run:  python benchmarks/bench_hertz.py [--n 100] [--steps 2000] [--repeat 5]
"""

from __future__ import annotations

import argparse

from bench_box_contact import per_step, scene

DT = 2e-6  # [s], below both laws' step estimates for these scenes
LAWS = ("linear", "hertz")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print("| scene | path | us/step linear | us/step Hertz | contact rows | extra ns/row |")
    print("|---|---|---|---|---|---|")
    for planar in (False, True):
        for stacked in (False, True):
            sims = [scene("box", args.n, stacked, True, planar, law, DT) for law in LAWS]
            linear, hertz = (1e6 * per_step(sim, args.steps, args.repeat) for sim in sims)
            rows, rows_h = (int(sim.boxes.rows.n[0]) for sim in sims)
            assert rows == rows_h
            name = "boxes stacked in pairs" if stacked else "boxes on the floor"
            path = "planar" if planar else "3D"
            extra = (hertz - linear) / rows * 1e3
            print(f"| {name} | {path} | {linear:.1f} | {hertz:.1f} | {rows} | {extra:.1f} |")


if __name__ == "__main__":
    main()

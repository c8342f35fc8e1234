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
import statistics
import time

import numpy as np

from dominowave.dem import Material, Scene

HALF = np.array([0.012, 0.004, 0.024])  # box outer half-extents [m]
ROUND = 0.001  # rounding radius [m]
DT = 2e-6  # [s], below both laws' step estimates for these scenes


def scene(law, n, stacked, planar):
    """n boxes (or n stacks of two) resting on a floor under the normal law ``law``."""
    s = Scene(gravity=(0.0, 0.0, -9.81), normal_law=law)
    stiffness = {"kn": 1e5} if law == "linear" else {"young": 1e8}
    m = s.add_material(Material(density=1000.0, friction=0.3, restitution=0.5, **stiffness))
    s.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    blocked = "x y rx ry rz" if stacked else ("y rx rz" if planar else "")
    for k in range(n):
        s.add_box((0.06 * k, 0.0, HALF[2]), HALF, ROUND, m, blocked=blocked)
        if stacked:
            s.add_box((0.06 * k, 0.0, 3 * HALF[2]), HALF, ROUND, m, blocked=blocked)
    sim = s.build(dt=DT, track_energy=False, record_pairs=False, impact_speed=0.1)
    sim.planar_kernels = planar
    return sim


def per_step(sim, steps, repeat):
    """Median CPU time per step [us] and the contact rows at the end."""
    sim.run(n_steps=steps)  # warm-up (compilation, settling)
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        sim.run(n_steps=steps)
        times.append((time.process_time() - t0) / steps * 1e6)
    return statistics.median(times), int(sim.boxes.rows.n[0])


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
            timed = [
                per_step(scene(law, args.n, stacked, planar), args.steps, args.repeat)
                for law in ("linear", "hertz")
            ]
            (linear, rows), (hertz, rows_h) = timed
            assert rows == rows_h
            name = "boxes stacked in pairs" if stacked else "boxes on the floor"
            path = "planar" if planar else "3D"
            extra = (hertz - linear) / rows * 1e3
            print(f"| {name} | {path} | {linear:.1f} | {hertz:.1f} | {rows} | {extra:.1f} |")


if __name__ == "__main__":
    main()

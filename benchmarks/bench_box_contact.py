"""Cost of a rounded-cuboid contact against a sphere contact in the DEM engine.

Scenes of N bodies on a floor, each timed per step (CPU time, median of --repeat runs of
--steps steps after a warm-up), and the same bodies hovering without contacts (no
gravity, far above the floor): the difference per contact is the cost of one contact
(geometry + law + its share of the driver).  Pairs: N bodies resting on the floor
(sphere-wall: 1 contact; box-wall: 4 points, 3D; 2 points, planar) and N two-body
stacks with x and y translations blocked (sphere-sphere; box-box: 4 points).  The hover
scenes also give the per-step cost of the bodies alone, which for boxes includes the
all-pairs bounding-sphere search of boxes.py.

Run:  python benchmarks/bench_box_contact.py [--n 100] [--steps 2000] [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from dominowave.dem import Material, Scene

R = 0.005  # sphere radius [m]
HALF = np.array([0.012, 0.004, 0.024])  # box outer half-extents [m]
ROUND = 0.001


def scene(kind, n, stacked, resting, planar, law="linear", dt=None):
    """n bodies (or n stacks of two) of `kind` on a floor; hovering if not resting.  Box
    contacts obey the normal ``law`` (materials: k_n = 1e5 N/m, or E = 1e8 Pa for
    Hertz); ``dt`` [s] default: 0.05 of the step estimate (Hertz: impacts at 0.1 m/s)."""
    g = (0.0, 0.0, -9.81) if resting else (0.0, 0.0, 0.0)
    s = Scene(gravity=g, normal_law=law)
    stiffness = {"kn": 1e5} if law == "linear" else {"young": 1e8}
    m = s.add_material(Material(density=1000.0, friction=0.3, restitution=0.5, **stiffness))
    s.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    blocked = "x y rx ry rz" if stacked else ""
    if planar:
        blocked = "x y rx ry rz" if stacked else "y rx rz"
    lift = 0.0 if resting else 1.0
    for k in range(n):
        x = 0.06 * k
        if kind == "sphere":
            s.add_sphere((x, 0.0, R + lift), R, m, blocked=blocked)
            if stacked:
                s.add_sphere((x, 0.0, 3 * R + lift + (0.05 if not resting else 0.0)), R, m,
                             blocked=blocked)  # fmt: skip
        else:
            s.add_box((x, 0.0, HALF[2] + lift), HALF, ROUND, m, blocked=blocked)
            if stacked:
                z = 3 * HALF[2] + lift + (0.1 if not resting else 0.0)
                s.add_box((x, 0.0, z), HALF, ROUND, m, blocked=blocked)
    sim = s.build(dt=dt, safety=0.05, track_energy=False, record_pairs=False, impact_speed=0.1)
    sim.planar_kernels = planar
    return sim


def per_step(sim, steps, repeat):
    """Median CPU time per step [s] of ``repeat`` runs of ``steps`` after a warm-up."""
    sim.run(n_steps=steps)  # warm-up (compilation, settling)
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        sim.run(n_steps=steps)
        times.append((time.process_time() - t0) / steps)
    return statistics.median(times)


def count_contacts(sim):
    return int(np.sum(sim.contacts.overlap[: sim.contacts.n[0]] > 0.0)) + int(sim.boxes.rows.n[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(f"N = {args.n}, {args.steps} steps x {args.repeat}, CPU time (median)")
    print("| scene | path | us/step resting | us/step hovering | contacts (rows) | ns/contact |")
    print("|---|---|---|---|---|---|")
    for planar in (False, True):
        for kind in ("sphere", "box"):
            for stacked in (False, True):
                rest = scene(kind, args.n, stacked, True, planar)
                t_rest = per_step(rest, args.steps, args.repeat)
                contacts = count_contacts(rest)
                hover = scene(kind, args.n, stacked, False, planar)
                t_hover = per_step(hover, args.steps, args.repeat)
                assert count_contacts(hover) == 0
                what = f"{kind}{'es' if kind == 'box' else 's'}{' stacked' if stacked else ''}"
                ns = 1e9 * (t_rest - t_hover) / max(contacts, 1)
                print(
                    f"| {what} | {'planar' if planar else '3D'} | {1e6 * t_rest:.1f} | "
                    f"{1e6 * t_hover:.1f} | {contacts} | {ns:.0f} |"
                )


if __name__ == "__main__":
    main()

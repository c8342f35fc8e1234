"""Speed of the DEM engine (dominowave.dem), single thread.

Scenes
------
* packing: N equal spheres stacked on a simple cubic lattice in a box of 5 walls under
  gravity (every sphere touching its 6 neighbours: a settled packing's contact count),
  friction 0.3, local damping 0.2;
* clumps: a row of planar columns of 10 spheres (y rx rz blocked) standing on a
  frictional floor, the first one pushed: the domino-chain workload (300 spheres = the
  paper's chain).

For each scene and size: steps per second and nanoseconds per sphere-step (median of
``--repeat`` runs after a warm-up that also compiles), with the recorders off and on
(pairs + event log + trajectory every 100 steps), and a profile split into contact
detection (displacement check + Verlet-list rebuilds), contact forces and integration,
timed with compiled loops over each phase on the same state.

Run:  python benchmarks/bench_engine.py [--quick] [--repeat 5]
"""

from __future__ import annotations

import argparse
import copy
import time

import numpy as np
from numba import njit

from dominowave.dem import Material, Scene
from dominowave.dem.contact import build_verlet_list, compute_forces, needs_rebuild
from dominowave.dem.integrate import drift, kick, update_sphere_positions

R = 0.005


def packing(n: int, record: bool):
    side = int(np.ceil(n ** (1 / 3)))
    scene = Scene()
    m = scene.add_material(Material(density=1000.0, young=1e7, friction=0.3))
    L = side * 2 * R
    for point, normal in [
        ((0, 0, 0), (0, 0, 1)),
        ((0, 0, 0), (1, 0, 0)),
        ((L, 0, 0), (-1, 0, 0)),
        ((0, 0, 0), (0, 1, 0)),
        ((0, L, 0), (0, -1, 0)),
    ]:
        scene.add_wall(point, normal, m)
    k = 0
    for iz in range(side):
        for iy in range(side):
            for ix in range(side):
                if k == n:
                    break
                scene.add_sphere(((2 * ix + 1) * R, (2 * iy + 1) * R, (2 * iz + 1) * R), R, m)
                k += 1
    return scene.build(safety=0.1, damping=0.2, record_pairs=record)


def clump_row(n_spheres: int, record: bool, per_clump: int = 10):
    scene = Scene()
    floor = scene.add_material(Material(density=1000.0, young=1e7, friction=0.3))
    body = scene.add_material(Material(density=1000.0, young=1e7, friction=0.0))
    scene.add_wall((0, 0, 0), (0, 0, 1), floor)
    spacing = 0.6 * per_clump * 2 * R
    for c in range(n_spheres // per_clump):
        centres = np.zeros((per_clump, 3))
        centres[:, 0] = c * spacing
        centres[:, 2] = R + 2 * R * np.arange(per_clump)
        mats = [floor] + [body] * (per_clump - 1)
        scene.add_clump(
            centres, R, mats, blocked="y rx rz", angular_velocity=(0, 3.0 if c == 0 else 0.0, 0)
        )
    return scene.build(safety=0.1, record_pairs=record)


@njit(cache=True)
def _loop_detection(spheres, walls, bodies, mats, contacts, skin, n):
    rebuilt = 0
    for _ in range(n):
        if needs_rebuild(spheres, skin, contacts.n[0]):
            build_verlet_list(spheres, walls, bodies, mats, contacts, skin)
            rebuilt += 1
    return rebuilt


@njit(cache=True)
def _loop_rebuild(spheres, walls, bodies, mats, contacts, skin, n):
    for _ in range(n):
        build_verlet_list(spheres, walls, bodies, mats, contacts, skin)


@njit(cache=True)
def _loop_forces(bodies, spheres, walls, contacts, dt, ledger, changes, n):
    for _ in range(n):
        compute_forces(bodies, spheres, walls, contacts, dt, ledger, changes, False)


@njit(cache=True)
def _loop_integration(bodies, spheres, gravity, dt, damping, n):
    for _ in range(n):
        kick(bodies, gravity, dt, damping, True)
        drift(bodies, dt)
        update_sphere_positions(bodies, spheres)


def timed(fn, repeat):
    """Median CPU time of ``repeat`` calls [s] (process time: the machine is shared, and
    CPU time is what one core spends; the wall time is printed alongside)."""
    cpu, wall = [], []
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - w0)
    timed.last_wall = float(np.median(wall))
    return float(np.median(cpu))


def measure(make, n, steps, repeat):
    row = {"n": n}
    for record in (False, True):
        sim = make(n, record)
        sim.run(n_steps=2000)  # warm-up: compile, settle the first contacts

        def go(sim=sim, record=record):
            sim.run(n_steps=steps, trajectory_every=100 if record else 0)

        t = timed(go, repeat)
        key = "rec" if record else "bare"
        row[f"wall_us_step_{key}"] = 1e6 * timed.last_wall / steps
        row[f"us_step_{key}"] = 1e6 * t / steps
        row[f"ns_sphere_step_{key}"] = 1e9 * t / steps / n
    # profile: each phase in its own compiled loop, on copies of the same state
    sim = make(n, False)
    sim.run(n_steps=2000)
    rebuilds0 = sim.rec.n_rebuilds[0]
    sim.run(n_steps=steps)
    rebuild_rate = (sim.rec.n_rebuilds[0] - rebuilds0) / steps
    s = sim.settings
    b, sp, c = copy.deepcopy(sim.bodies), copy.deepcopy(sim.spheres), copy.deepcopy(sim.contacts)
    ledger = np.zeros(3)
    check = timed(lambda: _loop_detection(sp, sim.walls, b, sim.mats, c, s.skin, steps), repeat)
    n_build = max(1, steps // 50)
    build = timed(lambda: _loop_rebuild(sp, sim.walls, b, sim.mats, c, s.skin, n_build), repeat)
    forces = timed(
        lambda: _loop_forces(b, sp, sim.walls, c, s.dt, ledger, sim.rec.changes, steps), repeat
    )
    integ = timed(lambda: _loop_integration(b, sp, s.gravity, s.dt, s.damping, steps), repeat)
    row["rebuild_every"] = 1.0 / rebuild_rate if rebuild_rate > 0 else np.inf
    row["us_detect"] = 1e6 * (check / steps + rebuild_rate * build / n_build)
    row["us_forces"] = 1e6 * forces / steps
    row["us_integrate"] = 1e6 * integ / steps
    row["contacts"] = int(c.active[: c.n[0]].sum())
    row["candidates"] = int(c.n[0])
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="small sizes only")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    sizes = [100, 300, 1000] if args.quick else [100, 300, 1000, 3000, 10000]
    print(
        "| scene | spheres | us/step | ns/sphere-step | us/step recording | ns/sphere-step "
        "recording | steps/s | wall us/step | detect us | forces us | integrate us | "
        "rebuild every | contacts/candidates |"
    )
    print("|" + "---|" * 13)
    for name, make in (("packing", packing), ("clumps", clump_row)):
        for n in sizes:
            steps = max(2000, int(2e6 / n))
            r = measure(make, n, steps, args.repeat)
            print(
                f"| {name} | {n} | {r['us_step_bare']:.2f} | {r['ns_sphere_step_bare']:.1f} | "
                f"{r['us_step_rec']:.2f} | {r['ns_sphere_step_rec']:.1f} | "
                f"{1e6 / r['us_step_bare']:.3g} | {r['wall_us_step_bare']:.2f} | "
                f"{r['us_detect']:.2f} | {r['us_forces']:.2f} | "
                f"{r['us_integrate']:.2f} | {r['rebuild_every']:.0f} steps | "
                f"{r['contacts']}/{r['candidates']} |",
                flush=True,
            )


if __name__ == "__main__":
    main()

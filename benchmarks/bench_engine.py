"""Speed of the DEM engine (dominowave.dem), single thread.

Scenes (both at the default time step, safety 0.02, so that the rebuild rate and the
simulated time per CPU second are those of a real run)
------
* packing: N equal spheres on a simple cubic lattice with 0.1 mm gaps (spacing 2.02 R,
  solid fraction 0.51) in a box of 5 walls under gravity, with random velocities of
  0.5 m/s: a dense agitated packing in which contacts form and end all the time and the
  Verlet list is rebuilt every ~1000 steps; friction 0.3, local damping 0.2;
* clumps: a toppling row of planar columns of 10 spheres (y rx rz blocked) on a
  frictional floor, spacing 0.6 of the height; every other column starts tilted towards
  its neighbour (0.3 mm from it, about 0.6 rad) and rotating at 3 rad/s, so
  domino-domino collisions happen all along the row during the measurement (the
  domino-chain workload; 300 spheres = the paper's chain).

For each scene and size: steps per second, nanoseconds per sphere-step and simulated
seconds per CPU second (median of ``--repeat`` runs after a warm-up that also compiles),
with the recorders off and on (pairs + event log + trajectory every 100 steps), and a
profile split into contact detection (displacement check + Verlet-list rebuilds), contact
forces and integration, timed with compiled loops over each phase on the same state.

Run:  python benchmarks/bench_engine.py [--quick] [--repeat 5]
"""

from __future__ import annotations

import argparse
import copy
import time
from pathlib import Path

import numpy as np
from numba import njit

from dominowave.dem import Material, Scene
from dominowave.dem.contact import (
    build_verlet_list,
    compute_forces,
    compute_forces_planar,
    needs_rebuild,
)
from dominowave.dem.integrate import (
    drift,
    kick,
    update_listed_sphere_positions,
    update_sphere_positions,
)
from dominowave.dem.laws.tangential import SHEAR_CONTACT_POINT
from dominowave.kernel_cache import install

# the cached kernels below inline the package's: stale with any change of it
install(Path(__file__).parent)

R = 0.005


def packing(n: int, record: bool):
    side = int(np.ceil(n ** (1 / 3)))
    pitch = 2.02 * R
    scene = Scene()
    m = scene.add_material(Material(density=1000.0, young=1e7, friction=0.3))
    L = side * pitch
    for point, normal in [
        ((0, 0, 0), (0, 0, 1)),
        ((0, 0, 0), (1, 0, 0)),
        ((L, 0, 0), (-1, 0, 0)),
        ((0, 0, 0), (0, 1, 0)),
        ((0, L, 0), (0, -1, 0)),
    ]:
        scene.add_wall(point, normal, m)
    rng = np.random.default_rng(0)
    k = 0
    for iz in range(side):
        for iy in range(side):
            for ix in range(side):
                if k == n:
                    break
                centre = (np.array([ix, iy, iz]) + 0.5) * pitch
                scene.add_sphere(centre, R, m, velocity=rng.normal(size=3) * 0.5)
                k += 1
    return scene.build(damping=0.2, record_pairs=record)


def clump_row(n_spheres: int, record: bool, per_clump: int = 10):
    scene = Scene()
    floor = scene.add_material(Material(density=1000.0, young=1e7, friction=0.3))
    body = scene.add_material(Material(density=1000.0, young=1e7, friction=0.0))
    scene.add_wall((0, 0, 0), (0, 0, 1), floor)
    spacing = 0.6 * per_clump * 2 * R
    upright = 2 * R * np.arange(per_clump)
    tilt = _leaning_tilt(upright, spacing, gap=3e-4)
    for c in range(n_spheres // per_clump):
        pushed = c % 2 == 0
        angle = tilt if pushed else 0.0
        axis = np.array([np.sin(angle), 0.0, np.cos(angle)])
        centres = np.array([c * spacing, 0.0, R]) + upright[:, None] * axis
        mats = [floor] + [body] * (per_clump - 1)
        scene.add_clump(
            centres, R, mats, blocked="y rx rz", angular_velocity=(0, 3.0 if pushed else 0.0, 0)
        )
    return scene.build(record_pairs=record)


def _leaning_tilt(heights, spacing, gap):
    """Largest tilt [rad] about the base sphere at which the column's spheres stay
    ``gap`` [m] away from the upright neighbour at ``spacing``."""
    neighbour = np.stack([spacing + 0 * heights, heights], axis=1)
    for tilt in np.arange(0.3, 1.2, 1e-4):
        mine = np.stack([heights * np.sin(tilt), heights * np.cos(tilt)], axis=1)
        dist = np.linalg.norm(mine[:, None] - neighbour[None], axis=2).min()
        if dist < 2 * R + gap:
            return tilt - 1e-4
    raise ValueError(f"spacing = {spacing} m: the columns never touch")


# The phase loops are compiled like the engine's run_loop, without numba's reference
# counting (engine.py): otherwise each call would pay atomic reference-count updates of
# every array of the state tuples, which the engine does not.


@njit(cache=True, _nrt=False)
def _loop_detection(spheres, walls, bodies, mats, contacts, skin, n, planar):
    rebuilt = 0
    for _ in range(n):
        if needs_rebuild(bodies, skin, contacts.n[0]):
            update_sphere_positions(bodies, spheres, planar)
            build_verlet_list(spheres, walls, bodies, mats, contacts, skin)
            rebuilt += 1
    return rebuilt


@njit(cache=True, _nrt=False)
def _loop_rebuild(spheres, walls, bodies, mats, contacts, skin, n, planar):
    for _ in range(n):
        update_sphere_positions(bodies, spheres, planar)
        build_verlet_list(spheres, walls, bodies, mats, contacts, skin)


@njit(cache=True, _nrt=False)
def _loop_forces(bodies, spheres, walls, contacts, dt, ledger, changes, lag, n, planar):
    kinematics = SHEAR_CONTACT_POINT
    for _ in range(n):
        if planar:  # (the kernel the engine runs on a planar scene: contact._sphere_driver)
            compute_forces_planar(
                bodies, spheres, walls, contacts, dt, ledger, changes, lag, False, kinematics
            )
        else:
            compute_forces(
                bodies, spheres, walls, contacts, dt, ledger, changes, lag, False, kinematics
            )


@njit(cache=True, _nrt=False)
def _loop_integration(bodies, spheres, gravity, dt, damping, n, planar):
    for _ in range(n):
        kick(bodies, gravity, dt, damping, True, planar)
        drift(bodies, dt, planar)
        update_listed_sphere_positions(bodies, spheres, planar)


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
        sim.run(n_steps=500)  # warm-up: compile (the collisions fall in the timed runs)

        def go(sim=sim, record=record):
            sim.run(n_steps=steps, trajectory_every=100 if record else 0)

        t = timed(go, repeat)
        key = "rec" if record else "bare"
        if record:  # distinct body-body contacts that began during the timed runs
            row["collisions"] = int(np.triu(sim.pairs.n_contacts, 1).sum())
        row[f"wall_us_step_{key}"] = 1e6 * timed.last_wall / steps
        row[f"us_step_{key}"] = 1e6 * t / steps
        row[f"ns_sphere_step_{key}"] = 1e9 * t / steps / n
        row[f"sim_per_cpu_{key}"] = sim.dt * steps / t  # simulated s per CPU s
    # profile: each phase in its own compiled loop, on copies of the same state
    sim = make(n, False)
    sim.run(n_steps=2000)
    rebuilds0 = sim.rec.n_rebuilds[0]
    sim.run(n_steps=steps)
    rebuild_rate = (sim.rec.n_rebuilds[0] - rebuilds0) / steps
    s = sim.settings
    planar = s.planar  # (the kernels of the runs above)
    b, sp, c = copy.deepcopy(sim.bodies), copy.deepcopy(sim.spheres), copy.deepcopy(sim.contacts)
    ledger = np.zeros(3)
    # compile / load each phase loop before timing it
    walls, mats = sim.walls, sim.mats
    _loop_detection(sp, walls, b, mats, c, s.skin, 1, planar)
    _loop_rebuild(sp, walls, b, mats, c, s.skin, 1, planar)
    changes, lag = sim.rec.changes, sim.rec.change_lag
    _loop_forces(b, sp, walls, c, s.dt, ledger, changes, lag, 1, planar)
    _loop_integration(b, sp, s.gravity, s.dt, s.damping, 1, planar)
    check = timed(lambda: _loop_detection(sp, walls, b, mats, c, s.skin, steps, planar), repeat)
    n_build = max(1, steps // 50)
    build = timed(lambda: _loop_rebuild(sp, walls, b, mats, c, s.skin, n_build, planar), repeat)
    forces = timed(
        lambda: _loop_forces(b, sp, walls, c, s.dt, ledger, changes, lag, steps, planar),
        repeat,
    )
    integ = timed(
        lambda: _loop_integration(b, sp, s.gravity, s.dt, s.damping, steps, planar), repeat
    )
    row["rebuild_every"] = 1.0 / rebuild_rate if rebuild_rate > 0 else np.inf
    row["us_detect"] = 1e6 * (check / steps + rebuild_rate * build / n_build)
    row["us_forces"] = 1e6 * forces / steps
    row["us_integrate"] = 1e6 * integ / steps
    row["contacts"] = int(np.sum(c.overlap[: c.n[0]] > 0.0))
    body_body = (c.j[: c.n[0]] >= 0) & (c.overlap[: c.n[0]] > 0.0)
    row["body_contacts"] = int(body_body.sum())
    row["dt"] = s.dt
    row["candidates"] = int(c.n[0])
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="small sizes only")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    sizes = [100, 300, 1000] if args.quick else [100, 300, 1000, 3000, 10000]
    print(
        "| scene | spheres | dt [s] | us/step | ns/sphere-step | us/step recording | "
        "ns/sphere-step recording | steps/s | simulated s per CPU s | wall us/step | "
        "detect us | forces us | integrate us | rebuild every | contacts (sphere-sphere)"
        "/candidates | body-body contacts during the runs |"
    )
    print("|" + "---|" * 16)
    for name, make in (("packing", packing), ("clumps", clump_row)):
        for n in sizes:
            steps = max(2000, int(2e6 / n))
            r = measure(make, n, steps, args.repeat)
            print(
                f"| {name} | {n} | {r['dt']:.3g} | {r['us_step_bare']:.2f} | "
                f"{r['ns_sphere_step_bare']:.1f} | "
                f"{r['us_step_rec']:.2f} | {r['ns_sphere_step_rec']:.1f} | "
                f"{1e6 / r['us_step_bare']:.3g} | {r['sim_per_cpu_bare']:.3g} | "
                f"{r['wall_us_step_bare']:.2f} | "
                f"{r['us_detect']:.2f} | {r['us_forces']:.2f} | "
                f"{r['us_integrate']:.2f} | {r['rebuild_every']:.0f} steps | "
                f"{r['contacts']} ({r['body_contacts']})/{r['candidates']} | "
                f"{r['collisions']} |",
                flush=True,
            )


if __name__ == "__main__":
    main()

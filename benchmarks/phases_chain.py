"""Where a step of the domino chain spends its time, measured in situ (engines only).

The chain of bench_chain.py (N dominoes) is run to step S; from that state a compiled copy
of the engine's step (list builds, contact forces, body pass, sphere placement: the
kernels run_loop calls in its steps without recorders) runs K steps, with one phase
changed at a time:

* ``static``: the body pass with dt = 0 (the same work, no motion, so no list builds);
* ``static, no forces``: besides, no contact forces;

so that forces = static - (static, no forces), motion and builds = all - static.  The
cost of one list build (with the placement of every sphere) is timed alone.  Min of R
runs each, interleaved (the VM's speed drifts between blocks of runs).

Run:  python benchmarks/phases_chain.py [--n 300] [--at 200000] [--steps 5000] [--repeat 5]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from bench_chain import case
from numba import njit

from dominowave.dem import contact, engine, integrate
from dominowave.kernel_cache import install

# the cached kernels below inline the package's: stale with any change of it
install(Path(__file__).parent)


@njit(cache=True, _nrt=False)
def _steps(bodies, spheres, walls, mats, contacts, settings, rec, n_steps, forces, still):
    """n_steps engine steps (run_loop's fused path); ``forces`` False: no contact forces;
    the body pass with the settings ``still`` (dt = 0) if given a different dt."""
    rebuild_due = contact.needs_rebuild(bodies, settings.skin, contacts.n[0])
    first, stop = engine._moving_range(bodies)  # (no releases here: no bookkeeping)
    builds = 0
    for _ in range(n_steps):
        if rebuild_due:
            integrate.update_sphere_positions(bodies, spheres, settings.planar)
            contact.build_verlet_list(spheres, walls, bodies, mats, contacts, settings.skin)
            builds += 1
        if forces:
            if settings.planar:
                contact.compute_forces_planar(
                    bodies,
                    spheres,
                    walls,
                    contacts,
                    settings.dt,
                    rec.ledger,
                    rec.changes,
                    rec.change_lag,
                    False,
                    mats.shear_kinematics[0],
                )
            else:
                contact.compute_forces(
                    bodies,
                    spheres,
                    walls,
                    contacts,
                    settings.dt,
                    rec.ledger,
                    rec.changes,
                    rec.change_lag,
                    False,
                    mats.shear_kinematics[0],
                )
        rebuild_due = engine._advance_bodies(bodies, still, first, stop)
        integrate.update_listed_sphere_positions(bodies, spheres, settings.planar)
    return builds


@njit(cache=True, _nrt=False)
def _builds(bodies, spheres, walls, mats, contacts, skin, planar, n):
    for _ in range(n):
        integrate.update_sphere_positions(bodies, spheres, planar)
        contact.build_verlet_list(spheres, walls, bodies, mats, contacts, skin)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--at", type=int, default=200_000, help="step of the state profiled")
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    chain = case(args.n)
    sim, _ = chain.build(chain.resolve(None), record=False, track_energy=False)
    sim.run(n_steps=args.at)
    state = sim.get_state()
    s = sim.settings
    c = sim.contacts
    n = int(c.n[0])
    active = c.overlap[:n] > 0.0
    print(
        f"N = {args.n} at step {args.at} (planar kernels: {s.planar}): {n} candidate pairs, "
        f"{active.sum()} active ({np.sum(active & (c.j[:n] < 0))} on the floor), "
        f"{sim.spheres.n_listed[0]} listed spheres"
    )
    cases = {"all": (True, s), "static": (True, s._replace(dt=0.0))}
    cases["static, no forces"] = (False, s._replace(dt=0.0))
    times = {name: [] for name in cases}
    builds = {}
    for r in range(args.repeat + 1):  # (the first round compiles or loads the loops)
        for name, (forces, still) in cases.items():
            sim.set_state(state)
            start = time.perf_counter()
            builds[name] = _steps(
                sim.bodies, sim.spheres, sim.walls, sim.mats, sim.contacts, s, sim.rec,
                args.steps, forces, still,
            )  # fmt: skip
            if r > 0:
                times[name].append((time.perf_counter() - start) / args.steps * 1e6)
    us = {name: min(t) for name, t in times.items()}
    for name in cases:
        print(f"  {name}: {us[name]:.2f} us/step ({builds[name]} list builds)")
    print(f"  -> contact forces {us['static'] - us['static, no forces']:.2f} us/step")
    print(f"  -> motion and list builds {us['all'] - us['static']:.2f} us/step")
    print(f"  -> body pass (dt = 0), placement, loop {us['static, no forces']:.2f} us/step")
    sim.set_state(state)
    c = sim.contacts
    n_build = 200
    per_build = []
    for _ in range(args.repeat + 1):
        start = time.perf_counter()
        _builds(sim.bodies, sim.spheres, sim.walls, sim.mats, c, s.skin, s.planar, n_build)
        per_build.append((time.perf_counter() - start) / n_build * 1e6)
    print(f"  one list build with the placement of every sphere: {min(per_build[1:]):.1f} us")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Where a step of the box chain spends its time: search, manifold, law, list builds, rest.

The box chain of ``box_chain_speed.py`` (held dominoes, as the clump chain) is run to a
few moments of its wave; at each, every phase is timed in its own compiled loop on the
same state (CPU time, median of --repeat loops of --steps calls; the loops compiled as the
engine's, without numba's reference counting):

* step: ``Simulation.run`` per step over the next --steps steps (engines only), on a copy
  of the chain;
* search: the pairs to visit (``boxes._visit_pairs``: the candidates of the boxes that
  are not held, kept from step to step, so here read back) and the tests of
  ``boxes.box_forces`` on them (bounding spheres, box-wall support), without the geometry;
* manifold: search plus the contact geometry (``shapes``) of the pairs that pass;
* forces: ``box_forces`` entire; law = forces - manifold (contact law, shear history,
  row bookkeeping, applying the forces);
* list: one build of the candidate list times the builds per step of the run;
* rest: step - forces - list (integration, the sphere kernels of an empty sphere set,
  the loop's bookkeeping).

Phases timed in their own loops miss what the run adds (branches and caches shared with
the other phases): ``box_phases.py`` times them in situ.

Run:  python benchmarks/box_profile.py [--n 30] [--model 2d] [--at 100 3000 10000]
"""

from __future__ import annotations

import argparse
import copy
import statistics
import time
from pathlib import Path

import numpy as np
from box_chain_speed import box_chain
from numba import njit

from dominowave.chain import ChainParams, DominoChain
from dominowave.dem.boxes import (
    _manifold,
    _partner,
    _partner_range,
    _source,
    _visit_pairs,
    _within_reach,
    box_forces,
    build_box_candidates,
)
from dominowave.kernel_cache import install

# the cached kernels below inline the package's: stale with any change of it
install(Path(__file__).parent)


@njit(cache=True, error_model="numpy", _nrt=False)
def _search(bodies, boxes, walls, planar, reps):
    nx, nw = boxes.body.shape[0], walls.point.shape[0]
    count = 0
    for _ in range(reps):
        for g in range(_visit_pairs(bodies, boxes, nx, nw)):
            a = _source(boxes, g)
            lo, hi = _partner_range(boxes, g, a, nx, nw)
            for kk in range(lo, hi):
                jj = _partner(boxes, a, kk, nx, nw)
                j = jj if jj < nx else -(jj - nx) - 1
                if _within_reach(bodies, boxes, walls, a, j, planar) >= 0.0:
                    count += 1
    return count


@njit(cache=True, error_model="numpy", _nrt=False)
def _search_and_manifold(bodies, boxes, walls, planar, reps):
    nx, nw = boxes.body.shape[0], walls.point.shape[0]
    points = 0
    for _ in range(reps):
        for g in range(_visit_pairs(bodies, boxes, nx, nw)):
            a = _source(boxes, g)
            lo, hi = _partner_range(boxes, g, a, nx, nw)
            for kk in range(lo, hi):
                jj = _partner(boxes, a, kk, nx, nw)
                j = jj if jj < nx else -(jj - nx) - 1
                margin = _within_reach(bodies, boxes, walls, a, j, planar)
                if margin >= 0.0:
                    points += _manifold(bodies, boxes, walls, a, j, planar, margin, True)
    return points


@njit(cache=True, error_model="numpy", _nrt=False)
def _forces(bodies, spheres, boxes, walls, mats, dt, planar, ledger, reps):
    for _ in range(reps):
        box_forces(bodies, spheres, boxes, walls, mats, dt, ledger, False, planar)


@njit(cache=True, error_model="numpy", _nrt=False)
def _builds(bodies, boxes, walls, skin, reps):
    n = 0
    for _ in range(reps):
        n = build_box_candidates(bodies, boxes, walls, skin)
    return n


def cpu(fn, reps, repeat):
    """Median CPU time [s] per call of fn(reps) over `repeat` runs."""
    fn(1)  # compilation
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        fn(reps)
        times.append((time.process_time() - t0) / reps)
    return statistics.median(times)


def profile(sim, steps, repeat):
    planar = bool(sim.settings.planar) if sim.rec.step[0] > 0 else sim.planar
    b, x, w, m = sim.bodies, sim.boxes, sim.walls, sim.mats
    us = {}
    step_times = []
    for _ in range(repeat):
        probe = copy.deepcopy(sim)
        t0 = time.process_time()
        probe.run(n_steps=steps)
        step_times.append((time.process_time() - t0) / steps)
    us["step"] = statistics.median(step_times)
    per_step = (probe.rec.n_rebuilds[0] - sim.rec.n_rebuilds[0]) / steps
    us["search"] = cpu(lambda k: _search(b, x, w, planar, k), steps, repeat)
    us["manifold"] = cpu(lambda k: _search_and_manifold(b, x, w, planar, k), steps, repeat)
    f_b, f_x = copy.deepcopy(b), copy.deepcopy(x)
    ledger = np.zeros(3)
    us["forces"] = cpu(
        lambda k: _forces(f_b, sim.spheres, f_x, w, m, sim.dt, planar, ledger, k), steps, repeat
    )
    l_x = copy.deepcopy(x)
    skin = sim.settings.skin
    us["list"] = per_step * cpu(lambda k: _builds(b, l_x, w, skin, k), 50, repeat)
    us = {k: 1e6 * v for k, v in us.items()}
    us["law"] = us["forces"] - us["manifold"]
    us["rest"] = us["step"] - us["forces"] - us["list"]
    moving = int(np.sum(b.held == 0))
    reach = _search(b, x, w, planar, 1)
    return us, moving, reach, int(x.rows.n[0]), int(x.n_cand[0]), per_step


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=30)
    parser.add_argument("--model", default="2d")
    parser.add_argument("--at", type=int, nargs="+", default=[100, 3000, 10000])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    chain = DominoChain(ChainParams(n_dominoes=args.n, model=args.model, stiffness_ratio=1e4))
    push = chain.resolve(None)
    clump, _ = chain.build(push, record=False, track_energy=False)
    sim = box_chain(chain, push.omega, clump.dt)
    print(f"N = {args.n}, model {args.model}, dt = {sim.dt:.3e} s; us per step (CPU, median "
          f"of {args.repeat} x {args.steps} calls)")  # fmt: skip
    print("| step | t [s] | moving | candidates | within reach | rows | list builds/step "
          "| step | search | manifold - search | law | list | rest |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for at in args.at:
        sim.run(n_steps=at - int(sim.rec.step[0]))
        us, moving, reach, rows, cand, builds = profile(sim, args.steps, args.repeat)
        print(
            f"| {at} | {sim.time:.3f} | {moving} | {cand} | {reach} | {rows} | {builds:.3f} | "
            f"{us['step']:.2f} | {us['search']:.2f} | {us['manifold'] - us['search']:.2f} | "
            f"{us['law']:.2f} | {us['list']:.2f} | {us['rest']:.2f} |"
        )


if __name__ == "__main__":
    main()

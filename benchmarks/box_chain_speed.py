"""A domino chain of rounded cuboids against the paper's clump chain: cost per step.

The clump chain is ``dominowave.chain.DominoChain`` (engines only: no event log, no energy
ledger).  The box chain is built here from the same parameters with ``Scene.add_box``: one
rounded cuboid per domino (height l, thickness s, width w, rounding s/20, the cuboid's
own mass density x l w s), standing on the same floor at the same positions, the same
contact stiffness per contact point, friction and time step; domino 0 is pushed with the
chain's default angular velocity about its front bottom edge (that edge at rest).  As in
the clump chain, dominoes 1.. are held until touched (``--free``: not held, each resting
on its four corners from the start, as before the engine had held boxes); a held domino
stands touching the floor (no overlap: it has no floor contact while held).  Both
are timed over the same steps (CPU time, median of --repeat windows, the two chains taking
turns); then a fresh box chain
runs until every domino has passed 45 degrees (or --until), and the wave speed is fitted
to those passage times (a rough measure: not the chain analysis of dominowave.chain,
which needs contact events).

Run:  python benchmarks/box_chain_speed.py [--n 30] [--model 2d] [--steps 20000] [--free]
      [--skin S]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
from scipy.spatial.transform import Rotation

from dominowave.chain import ChainParams, DominoChain
from dominowave.dem import Material, Scene


def box_chain(
    chain: DominoChain, omega: float, dt: float, held: bool = True, skin: float | None = None
):
    """The box version of ``chain`` (see module docstring); returns the Simulation.
    ``skin``: the Verlet skin [m] (default: one thickness, as the chain's boxes)."""
    p = chain.params
    half = np.array([p.thickness, p.width, p.height]) / 2
    r = p.thickness / 20
    scene = Scene(gravity=(0.0, 0.0, -p.g))
    kw = {"kn": p.contact_stiffness, "kt_ratio": p.kt_ratio, "restitution": p.restitution}
    face = scene.add_material(Material(density=p.density, friction=p.friction_dominoes, **kw))
    floor = scene.add_material(Material(density=p.density, friction=p.friction_floor, **kw))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), floor)
    mass = p.density * p.height * p.width * p.thickness
    sink = mass * p.g / (4 * p.contact_stiffness)  # four corners on the floor
    blocked = "y rx rz" if p.model == "2d" else ""
    for n, x in enumerate(chain.positions):
        hold = held and n > 0
        centre = np.array([x, 0.0, half[2] - (0.0 if hold else sink)])
        if n == 0:  # turning about the front bottom edge's floor contact
            w = np.array([0.0, omega, 0.0])
            v = np.cross(w, centre - np.array([x + half[0] - r, 0.0, 0.0]))
        else:
            w = v = np.zeros(3)
        # (friction between dominoes: the face material; floor: the floor material)
        scene.add_box(
            centre, half, r, face, blocked=blocked, velocity=v, angular_velocity=w, held=hold
        )
    skin = p.thickness if skin is None else skin
    sim = scene.build(dt=dt, track_energy=False, record_pairs=False, skin=skin)
    # the box chain has no lateral asymmetry: in 3D it stays in its plane and the engine
    # would take the planar kernels; the 3D chain is timed with the general ones
    sim.planar_kernels = p.model == "2d"
    return sim


def cpu_per_step(sims, steps, repeat):
    """Median CPU time per step [s] of each simulation over ``repeat`` consecutive windows
    of ``steps`` steps; the simulations take turns window by window, so that a change of
    the machine's load between windows affects each of them alike."""
    times = [[] for _ in sims]
    for _ in range(repeat):
        for sim, out in zip(sims, times, strict=True):
            t0 = time.process_time()
            sim.run(n_steps=steps)
            out.append((time.process_time() - t0) / steps)
    return [statistics.median(t) for t in times]


def tilts(sim):
    """Forward tilt [rad] of every domino (rotation about y)."""
    return np.array([Rotation.from_quat(q[[1, 2, 3, 0]]).as_rotvec()[1] for q in sim.bodies.quat])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=30)
    parser.add_argument("--model", default="2d")
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--until", type=float, default=3.0)
    parser.add_argument("--free", action="store_true", help="no held dominoes")
    parser.add_argument("--skin", type=float, default=None, help="Verlet skin [m]")
    args = parser.parse_args()
    chain = DominoChain(ChainParams(n_dominoes=args.n, model=args.model, stiffness_ratio=1e4))
    push = chain.resolve(None)
    clump, _ = chain.build(push, record=False, track_energy=False)
    box = box_chain(chain, push.omega, clump.dt, held=not args.free, skin=args.skin)
    clump.run(n_steps=100)  # compilation
    box.run(n_steps=100)
    t_clump, t_box = cpu_per_step((clump, box), args.steps, args.repeat)
    print(
        f"N = {args.n}, model {args.model}, dt = {clump.dt:.3e} s, {args.steps} steps, "
        f"box skin {box.settings.skin:.3g} m, list builds per step "
        f"{box.rec.n_rebuilds[0] / max(int(box.rec.step[0]), 1):.3f}"
    )
    print(f"clump chain: {1e6 * t_clump:.1f} us/step; box chain: {1e6 * t_box:.1f} us/step; "
          f"ratio box/clump = {t_box / t_clump:.2f}")  # fmt: skip
    # the wave: a fresh box chain, the first time each domino passes 45 degrees
    box = box_chain(chain, push.omega, clump.dt, held=not args.free, skin=args.skin)
    passed = np.full(args.n, np.nan)
    while box.time < args.until and np.isnan(passed).any():
        box.run(n_steps=200)
        passed[np.isnan(passed) & (tilts(box) > math.pi / 4)] = box.time
    fallen = np.isfinite(passed)
    print(f"box chain: {fallen.sum()} of {args.n} dominoes passed 45 deg by t = {box.time:.3f} s")
    tail = fallen & (np.arange(args.n) >= args.n // 3)
    if tail.sum() >= 3:
        speed = np.polyfit(passed[tail], chain.positions[tail], 1)[0]
        print(f"wave speed (45-degree passages, dominoes {args.n // 3}..): {speed:.3f} m/s")


if __name__ == "__main__":
    main()

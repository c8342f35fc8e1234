"""What a step of the box chain and of the clump chain consists of, timed in situ.

Both chains of ``box_chain_speed.py`` (the paper's clump chain and the same chain of
rounded cuboids, same dt, engines only) are run to step --at; from that state a compiled
copy of ``engine.run_loop``'s step -- the same kernels in the same order, for a run
without recorders, energy ledger or stop conditions, as the chain benchmarks run --
advances --steps steps and reads the processor's cycle counter between its phases (the
copy calls the sphere kernels in the box chain too, where they find nothing to do; a box
chain's own loop leaves them out, ``engine.SceneKind``):

* head: the loop's tests at the start of a step (time, buffer room, recorders due);
* list: the Verlet-list builds (the spheres': placement of every sphere and the
  linked-cell search; the boxes': box-box/box-wall and box-sphere candidates);
* spheres: ``compute_forces`` (or its planar kernel): the zeroing of every body's force
  and torque and the sphere contacts (a step without sphere pairs, as in the box chain:
  the loop's own zeroing);
* boxes: ``box_forces`` (with the box-sphere points in a scene with spheres), split (a
  second pass, --split) by timing its parts on the same state just before it: the
  selection of the pairs to visit (``boxes._visit_pairs``), the bounding tests
  (``boxes._within_reach``) and the contact geometry (``boxes._manifold``) of the box
  pairs within reach; law = the rest of box_forces (contact law, shear history, rows,
  applying the forces);
* bookkeeping: contact onsets and ends (held-body release) and the stop conditions;
* advance: the fused kick-drift pass with the displacement test (99 of 100 steps);
* check: the check steps (every ``check_every`` steps): separate kick, the energies and
  finiteness tests, drift, the displacement test over every body;
* placement: the placement of the listed spheres, the clock.

Each phase is charged one counter read (its cost, measured alone, is subtracted).  The
counter runs on while the process waits for a core, so on a loaded machine the cycles
overstate every phase in proportion: the table gives each phase's share of the cycles
(median of --repeat runs) times the CPU time per step of ``Simulation.run`` over the same
steps from the same state (median of --repeat), and the ratio of the instrumented wall
time to that CPU time (``wall/cpu``: 1 on an idle machine, plus the counter reads).

With ``--chain standard`` the standard 40-domino 3D chain (standard_chain_vs_mujoco.py) as
the package's defaults build it is profiled instead.

Run:  python benchmarks/box_phases.py [--n 30] [--model 2d] [--at 10000] [--steps 5000]
      [--chain paper|standard]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
from box_chain_speed import box_chain
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from dominowave.chain import ChainParams, DominoChain, Push
from dominowave.chain.presets import standard_domino
from dominowave.dem import box_sphere, boxes, contact, engine, integrate
from dominowave.dem.energy import E_GRAVITATIONAL, energies

PHASES = (
    "head", "list: spheres", "list: boxes", "spheres", "boxes: visit", "boxes: reach",
    "boxes: manifold", "boxes", "bookkeeping", "advance", "check", "placement",
)  # fmt: skip
(HEAD, LIST_S, LIST_B, SPHERES, VISIT, REACH, MANIFOLD, BOXES, BOOK, ADVANCE, CHECK,
 PLACE) = range(len(PHASES))  # fmt: skip


@intrinsic
def _cycles(typingctx):
    """The processor's cycle counter (LLVM readcyclecounter: rdtsc on x86)."""

    def codegen(context, builder, signature, args):
        fnty = ir.FunctionType(ir.IntType(64), [])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.readcyclecounter")
        return builder.call(fn, [])

    return types.int64(), codegen


@njit(cache=False, _nrt=False)
def _read_cost(n):
    """Cycles of one counter read: the least mean over 100 batches of n."""
    best = 1 << 62
    for _ in range(100):
        t0 = _cycles()
        for _ in range(n):
            _cycles()
        best = min(best, _cycles() - t0)
    return best / n


@njit(cache=False, _nrt=False)
def _split_boxes(bodies, bx, walls, pl, acc):
    """The parts of box_forces, each timed on the current state (they only write
    scratch that box_forces writes again): visit, bounding tests, geometry."""
    nx, nw = bx.body.shape[0], walls.point.shape[0]
    t0 = _cycles()
    n_groups = boxes._visit_pairs(bodies, bx, nx, nw)
    t1 = _cycles()
    acc[VISIT] += t1 - t0
    reach_cycles = 0
    manifold_cycles = 0
    for g in range(n_groups):
        a = boxes._source(bx, g)
        lo, hi = boxes._partner_range(bx, g, a, nx, nw)
        for kk in range(lo, hi):
            jj = boxes._partner(bx, a, kk, nx, nw)
            j = jj if jj < nx else -(jj - nx) - 1
            t2 = _cycles()
            margin = boxes._within_reach(bodies, bx, walls, a, j, pl)
            t3 = _cycles()
            reach_cycles += t3 - t2
            if margin >= 0.0:
                boxes._manifold(bodies, bx, walls, a, j, pl, margin, True)
                manifold_cycles += _cycles() - t3
    acc[REACH] += reach_cycles
    acc[MANIFOLD] += manifold_cycles


@njit(cache=False, _nrt=False)
def _timed_steps(bodies, spheres, walls, mats, contacts, settings, rec, bx, n_steps, split, acc):
    """n_steps steps of engine.run_loop (no recorders, no ledger, no stop condition),
    cycles per phase added to ``acc``; returns the list builds."""
    dt = settings.dt
    pl = settings.planar
    kin = rec.energy_now  # (the check step's energies)
    has_boxes = bx.body.shape[0] > 0
    if has_boxes:
        bx.n_groups[0] = -1
    rebuild_due = contact.needs_rebuild(bodies, settings.skin, contacts.n[0])
    if has_boxes and boxes.released_since_build(bodies, bx):
        bx.n_cand[0] = -1
    first, stop = engine._moving_range(bodies)
    builds = 0
    t0 = rec.clock[engine.CLOCK_TIME]
    for _ in range(n_steps):
        c0 = _cycles()
        t = rec.clock[engine.CLOCK_TIME]
        step = rec.step[0]
        room = contacts.i.shape[0] + (bx.changes.shape[0] if has_boxes else 0)
        traj_due = rec.traj_every[0] > 0 and step % rec.traj_every[0] == 0
        energy_due = rec.energy_every[0] > 0 and step % rec.energy_every[0] == 0
        if room < 0 or traj_due or energy_due:
            return -1
        c1 = _cycles()
        acc[HEAD] += c1 - c0
        if rebuild_due or (has_boxes and min(bx.n_cand[0], bx.n_sphere_cand[0]) < 0):
            integrate.update_sphere_positions(bodies, spheres, pl)
            contact.build_verlet_list(spheres, walls, bodies, mats, contacts, settings.skin)
            rec.n_rebuilds[0] += 1
            builds += 1
            c2 = _cycles()
            acc[LIST_S] += c2 - c1
            if has_boxes:
                boxes.build_box_candidates(bodies, bx, walls, settings.skin)
                box_sphere.build_box_sphere_candidates(bodies, spheres, bx, walls, settings.skin)
            c1 = _cycles()
            acc[LIST_B] += c1 - c2
        if contacts.n[0] == 0:
            engine._zero_forces(bodies)
            n_changes = 0
        elif pl:
            n_changes = contact.compute_forces_planar(
                bodies, spheres, walls, contacts, dt, rec.ledger, rec.changes, rec.change_lag,
                step == 0, mats.shear_kinematics[0],
            )  # fmt: skip
        else:
            n_changes = contact.compute_forces(
                bodies, spheres, walls, contacts, dt, rec.ledger, rec.changes, rec.change_lag,
                step == 0, mats.shear_kinematics[0],
            )  # fmt: skip
        c2 = _cycles()
        acc[SPHERES] += c2 - c1
        released = False
        if has_boxes:
            if split:
                _split_boxes(bodies, bx, walls, pl, acc)
                c2 = _cycles()
            boxes.box_forces(bodies, spheres, bx, walls, mats, dt, rec.ledger, step == 0, pl)
            c3 = _cycles()
            acc[BOXES] += c3 - c2
            c2 = c3  # (the bookkeeping's start)
            if bx.n_changes[0] > 0:
                released = engine._bookkeep(
                    bodies, spheres, contacts, rec, settings, bx.changes, bx.change_lag,
                    bx.n_changes[0], t,
                )  # fmt: skip
        if n_changes > 0:
            released |= engine._bookkeep(
                bodies, spheres, contacts, rec, settings, rec.changes, rec.change_lag,
                n_changes, t,
            )  # fmt: skip
        if released:
            first, stop = engine._moving_range(bodies)
            if has_boxes:
                bx.n_groups[0] = -1
                if boxes.released_since_build(bodies, bx):
                    bx.n_cand[0] = -1
        code = -1  # (no stop condition: the quiet test with an infinite quiet time)
        if engine.quiet_reached(t, dt, max(rec.last_onset[0], t0), np.inf):
            code = 0
        c3 = _cycles()
        acc[BOOK] += c3 - c2
        check_due = (step + 1) % settings.check_every == 0 or code >= 0
        if not check_due:
            rebuild_due = engine._advance_bodies(bodies, settings, first, stop)
            c4 = _cycles()
            acc[ADVANCE] += c4 - c3
        else:
            integrate.kick(bodies, settings.gravity, dt, settings.damping,
                           settings.damp_gravity, pl)  # fmt: skip
            energies(bodies, contacts, settings.gravity, rec.ledger, kin)
            if has_boxes:
                boxes.box_energies(bx, kin)
            if not engine._finite(bodies) or kin[E_GRAVITATIONAL] != kin[E_GRAVITATIONAL]:
                return -1
            integrate.drift(bodies, dt, pl)
            rebuild_due = contact.needs_rebuild(bodies, settings.skin, contacts.n[0])
            c4 = _cycles()
            acc[CHECK] += c4 - c3
        integrate.update_listed_sphere_positions(bodies, spheres, pl)
        rec.clock[engine.CLOCK_TIME] = t + dt
        rec.step[0] = step + 1
        acc[PLACE] += _cycles() - c4
    return builds


def timed(sim, state, steps, split):
    """Cycles per phase over ``steps`` steps from ``state``, and the wall time [s]."""
    sim.set_state(state)
    sim._start_run(0, 0, False)
    acc = np.zeros(len(PHASES), np.int64)
    t0 = time.perf_counter()
    _timed_steps(
        sim.bodies, sim.spheres, sim.walls, sim.mats, sim.contacts, sim.settings, sim.rec,
        sim.boxes, steps, split, acc,
    )  # fmt: skip
    return acc, time.perf_counter() - t0


def cpu_step(sim, state, steps):
    sim.set_state(state)
    t0 = time.process_time()
    sim.run(n_steps=steps)
    return (time.process_time() - t0) / steps


def profile(name, sim, at, steps, repeat, rate, read):
    sim.run(n_steps=at)
    state = sim.get_state()
    moving = int(np.sum(sim.bodies.held == 0))
    rows = int(sim.boxes.rows.n[0]) if sim.boxes.body.shape[0] else 0
    ncontacts = int(np.sum(sim.contacts.overlap[: sim.contacts.n[0]] > 0.0))
    timed(sim, state, 10, True)  # compilation
    runs = {False: [], True: []}
    cpu = []
    for _ in range(repeat):
        for split in (False, True):
            acc, _ = timed(sim, state, steps, split)
            runs[split].append(acc)
        cpu.append(cpu_step(sim, state, steps))
    us = {}
    for split in (False, True):
        per = np.median(np.array(runs[split]), axis=0)
        us[split] = np.maximum(per - read, 0.0) / rate / steps * 1e6
    out = dict(zip(PHASES, us[False], strict=True))
    box_total = us[False][BOXES]
    parts = us[True][[VISIT, REACH, MANIFOLD]]
    scale = box_total / max(us[True][BOXES] + parts.sum(), 1e-12)  # (the split's share)
    out["boxes: visit"], out["boxes: reach"], out["boxes: manifold"] = parts * scale
    out["boxes: law"] = box_total - parts.sum() * scale
    # the counter runs on while the process waits for a core (a loaded machine): the
    # phases are shares of the CPU time per step, which such waits do not bias
    wall = sum(us[False])
    out["cpu"] = 1e6 * statistics.median(cpu)
    for k in list(out):
        if k != "cpu":
            out[k] *= out["cpu"] / wall
    out["wall/cpu"] = wall / out["cpu"]
    return name, at, moving, rows, ncontacts, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=30)
    ap.add_argument("--model", default="2d")
    ap.add_argument("--at", type=int, nargs="+", default=[10000])
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument(
        "--chain", choices=("paper", "standard"), default="paper",
        help="paper: the clump chain beside its box twin; standard: the standard 40-domino"
        " 3D chain of standard_chain_vs_mujoco.py as the package's defaults build it",
    )  # fmt: skip
    args = ap.parse_args()
    read = _read_cost(1000)
    _cycles_now()  # (compilation)
    t0, c0 = time.perf_counter(), _cycles_now()
    time.sleep(0.5)
    rate = (_cycles_now() - c0) / (time.perf_counter() - t0)
    chain = DominoChain(ChainParams(n_dominoes=args.n, model=args.model, stiffness_ratio=1e4))
    push = chain.resolve(None)
    what = "the standard chain" if args.chain == "standard" else f"N = {args.n}, model {args.model}"
    print(f"{what}; counter {rate / 1e9:.3f} GHz, one read "
          f"{read:.0f} cycles; us per step (CPU, shares of the cycles; median of "
          f"{args.repeat} x {args.steps} steps)")  # fmt: skip
    cols = ["head", "list: spheres", "list: boxes", "spheres", "boxes: visit", "boxes: reach",
            "boxes: manifold", "boxes: law", "bookkeeping", "advance", "check", "placement",
            "cpu", "wall/cpu"]  # fmt: skip
    print("| chain | step | moving | box rows | sphere contacts | " + " | ".join(cols) + " |")
    print("|---" * (5 + len(cols)) + "|")
    for at in args.at:
        if args.chain == "standard":
            sims = (("standard", standard_chain()),)
        else:
            clump, _ = chain.build(push, record=False, track_energy=False)
            sims = (("clump", clump), ("box", box_chain(chain, push.omega, clump.dt)))
        for name, sim in sims:
            name, at_, moving, rows, nc, us = profile(
                name, sim, at, args.steps, args.repeat, rate, read
            )
            vals = " | ".join(f"{us[c]:.2f}" for c in cols)
            print(f"| {name} | {at_} | {moving} | {rows} | {nc} | {vals} |", flush=True)


GAP, FRICTION, N = 0.00938, 0.3, 40
"""The standard chain of standard_chain_vs_mujoco.py (which needs MuJoCo to import)."""


def standard_chain():
    """The standard 40-domino 3D chain of standard_chain_vs_mujoco.py as the package's
    defaults build it (softened contact at T_c/10, dominoes held until touched), without
    recorders and without sleep (the timed loop has none, and the CPU time it is scaled
    to must be of the same steps)."""
    p = standard_domino(
        gap=GAP, floor="felt", n_dominoes=N, friction_dominoes=FRICTION, friction_floor=FRICTION
    )
    chain = DominoChain(p, sleep=False)
    sim, _ = chain.build(Push(omega=math.sqrt(p.g / p.height)), record=False, track_energy=False)
    return sim


@njit(cache=False, _nrt=False)
def _cycles_now():
    return _cycles()


if __name__ == "__main__":
    main()

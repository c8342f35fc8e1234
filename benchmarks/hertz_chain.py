"""A 3D chain of standard plastic dominoes with Hertz contacts, run to its end: CPU time.

The chain is ``chain.presets.standard_domino`` (48 x 24 x 7.5 mm box dominoes, the
nominal mass, friction and restitution of the shipped material data, the given floor and
gap, lateral asymmetry 0.01) with ``normal_law="hertz"``, E = --young, nu = --poisson,
as ``DominoChain`` builds it: every domino rests on the floor at its Hertz sink (--held:
dominoes 1.. held there until touched, as the clump chain's); domino 0 is pushed about
its front bottom edge with the chain's default push; time step ``--safety`` x the
engine's critical estimate (timestep.py) unless --dt. The run ends when the wave reaches
the last domino (its first contact with the one before), or when no body-body contact
has started for --quiet seconds (tested every --report simulated seconds), or at
--max-time-factor x the chain's max_time (the chain's own max_time, from the linear
theory's travel time, can end a Hertz run before the wave arrives). Reported: the step,
the steps, the CPU (process) time of the whole run (median of --repeat fresh runs, after
one compilation run of a few steps), the dominoes reached, the arrival times (first
contact with the previous domino) and the front speed fitted to the arrivals of the
second half; and, every --report seconds, the in-situ cost: CPU per step over the last
piece, the contact rows (points) of the last step, box-box and floor, and the candidate
box pairs of the Verlet list.

Run:  python benchmarks/hertz_chain.py [--n 100] [--gap 0.02] [--repeat 3] [--held]
      [--safety 0.02]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from dominowave.chain import DominoChain
from dominowave.chain.presets import standard_domino
from dominowave.dem import StopCondition


def hertz_chain(params, dt: float | None, safety: float) -> DominoChain:
    """The Hertz box chain of ``params`` (module docstring): the step ``dt`` [s], or (None)
    ``safety`` x the engine's critical estimate."""
    return DominoChain(params, dt=dt, safety=None if dt is not None else safety)


def build(chain: DominoChain):
    """A fresh simulation of ``chain`` as the chain analysis builds it, without the energy
    ledger (a pure timing; the trajectory is the same)."""
    sim, _ = chain.build(chain.resolve(None), record=True, track_energy=False)
    return sim


def reached(sim):
    """Dominoes the wave has reached: domino 0 and each that touched its predecessor."""
    n = np.arange(1, sim.n_bodies)
    return 1 + int(np.isfinite(sim.rec.first_contact[n - 1, n]).sum())


def profile_split(sim, times, steps=2000, repeat=3):
    """Print where a step goes at each of ``times`` [s] of the wave (box_profile.profile:
    each phase timed in its own compiled loop on the same state, median of ``repeat``
    loops of ``steps`` calls; search, manifold, law, list builds, rest)."""
    from box_profile import profile

    print(
        f"dt = {sim.dt:.3e} s; us per step (CPU, median of {repeat} x {steps} calls)\n"
        "| t [s] | reached | candidates | within reach | rows | step | search "
        "| manifold - search | law | list | rest |\n|---|---|---|---|---|---|---|---|---|---|---|"
    )
    for t in times:
        sim.run(until=t)
        us, _, reach, rows, cand, _ = profile(sim, steps, repeat)
        print(
            f"| {sim.time:.3f} | {reached(sim)} | {cand} | {reach} | {rows} | {us['step']:.1f} | "
            f"{us['search']:.1f} | {us['manifold'] - us['search']:.1f} | {us['law']:.1f} | "
            f"{us['list']:.2f} | {us['rest']:.1f} |",
            flush=True,
        )


def add_chain_arguments(parser: argparse.ArgumentParser, n: int) -> None:
    """The options of the chain: --n (default ``n``), --gap, --floor, --young, --poisson."""
    parser.add_argument("--n", type=int, default=n)
    parser.add_argument("--gap", type=float, default=0.02, help="clear gap d [m]")
    parser.add_argument("--floor", default="hardwood")
    parser.add_argument("--young", type=float, default=2.5e9)
    parser.add_argument("--poisson", type=float, default=0.35)


def chain_params(args: argparse.Namespace, held: bool | None):
    """The standard Hertz chain of the options (lateral asymmetry 0.01)."""
    return standard_domino(
        n_dominoes=args.n,
        gap=args.gap,
        floor=args.floor,
        lateral_asymmetry=0.01,
        young=args.young,
        normal_law="hertz",
        poisson=args.poisson,
        held=held,
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_chain_arguments(parser, n=100)
    parser.add_argument("--dt", type=float, default=None)
    parser.add_argument("--safety", type=float, default=0.02)
    parser.add_argument(
        "--max-time-factor", type=float, default=2.0, help="end at most at this x max_time"
    )
    parser.add_argument("--quiet", type=float, default=0.2, help="end: no onset for [s]")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--held", action="store_true", help="dominoes 1.. held until touched")
    parser.add_argument("--report", type=float, default=0.1, help="progress every [s]")
    parser.add_argument(
        "--profile-at",
        type=float,
        nargs="+",
        default=None,
        help="instead of the timed runs: the split of a step (box_profile.py) at these times [s]",
    )
    args = parser.parse_args()
    chain = hertz_chain(chain_params(args, held=args.held or None), args.dt, args.safety)

    def fresh():
        return build(chain)

    # the end: the wave reaches the last domino (its first contact with the one before),
    # or the quiet end, or --max-time
    end = args.max_time_factor * chain.max_time
    last_touched = StopCondition(touched_body=args.n - 1)

    if args.profile_at:
        profile_split(fresh(), args.profile_at)
        return
    fresh().run(n_steps=10)  # compilation
    times, sim = [], None
    for _ in range(args.repeat):
        sim = fresh()
        t0 = time.process_time()
        # (in pieces of --report simulated seconds, the progress printed: a long run;
        # the quiet end tested between pieces, on the engine's time of the last onset)
        while sim.time < end - 0.5 * sim.dt:
            steps, cpu = int(sim.rec.step[0]), time.process_time()
            sim.run(until=min(sim.time + args.report, end), stop=last_touched)
            rows = sim.boxes.rows
            box_box = int((rows.j[: rows.n[0]] >= 0).sum())
            per_step = (time.process_time() - cpu) / max(int(sim.rec.step[0]) - steps, 1)
            print(
                f"  t = {sim.time:.3f} s, {reached(sim)} dominoes reached, "
                f"CPU {time.process_time() - t0:.1f} s, {1e6 * per_step:.1f} us/step, "
                f"rows {rows.n[0]} ({box_box} box-box), candidates {sim.boxes.n_cand[0]}",
                flush=True,
            )
            if sim.time - sim.rec.last_onset[0] >= args.quiet or reached(sim) == args.n:
                break
        times.append(time.process_time() - t0)
    steps = int(sim.rec.step[0])
    touched = reached(sim)
    # arrival of the wave at domino n: its first contact with domino n - 1
    n = np.arange(1, args.n)
    arrival = sim.rec.first_contact[n - 1, n]
    hit = np.isfinite(arrival)
    tail = hit & (n >= args.n // 2)
    speed = np.polyfit(arrival[tail], chain.positions[n[tail]], 1)[0] if tail.sum() > 2 else np.nan
    print(
        f"N = {args.n}, gap {args.gap} m, E = {args.young:.3g} Pa, nu = {args.poisson}, "
        f"held {args.held}, dt = {sim.dt:.3e} s ({sim.dt / sim.critical_dt:.3g} of the critical "
        f"estimate), {steps} steps to t = {sim.time:.3f} s, "
        f"dominoes reached {touched} of {args.n}"
    )
    print(
        f"CPU time of the run: median {statistics.median(times):.1f} s of {args.repeat} "
        f"({', '.join(f'{t:.1f}' for t in times)}); "
        f"{1e6 * statistics.median(times) / steps:.2f} us/step"
    )
    last = int(n[hit][-1]) if hit.any() else 0
    print(
        f"wave: reached domino {last} at t = {arrival[last - 1]:.6f} s; front speed over "
        f"dominoes {args.n // 2}.. {speed:.4f} m/s; arrival at domino 1: {arrival[0]:.6f} s"
    )


if __name__ == "__main__":
    main()

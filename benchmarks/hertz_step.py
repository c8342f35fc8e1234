"""The time step of the Hertz box chain: convergence in ``safety`` and the real stability limit.

The chain of ``hertz_chain.py`` (standard plastic dominoes, Hertz contacts, E = --young,
nu = --poisson, dominoes 1.. held until touched) with --n dominoes, run to its end at
each step ``safety`` x the engine's critical estimate (timestep.py).  Reported per
safety: the step, the steps, the CPU (process) time, the dominoes reached, the arrival
times (first contact with the previous domino) against those of the smallest safety
(the reference: largest absolute and relative difference), the front speed fitted to the
arrivals of the second half, the energy dissipated (dashpots, friction) and the drift of
the total energy relative to the initial one (the ledger is on here).  A safety above 1
is an EXPERIMENT the engine refuses in normal use (``Scene.build`` rejects a step above its
estimate): the scene is built at the estimate and its step then set to safety x the
estimate, to find where the scheme really becomes unstable (the engine's run-time check,
an energy runaway or NaN, stops such a run: reported as "unstable").

Run:  python benchmarks/hertz_step.py [--n 20] [--safety 0.02 0.05 0.1 0.2 0.4]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from hertz_chain import add_chain_arguments, chain_params, reached

from dominowave.chain import DominoChain


def run_to_end(chain: DominoChain, safety: float, quiet: float):
    """Run the chain at ``safety`` (above 1: the step set past the estimate, module
    docstring) until no body-body contact started for ``quiet`` s or ``max_time``.
    Returns (sim, CPU seconds, initial total energy [J]) or (None, reason, nan) if the run
    blew up."""
    sim, _ = chain.build(chain.resolve(None), record=True, track_energy=True)
    e0 = sim.energy()["total"]
    if safety > 1.0:
        sim.settings = sim.settings._replace(dt=safety * sim.critical_dt)
    t0 = time.process_time()
    try:
        while sim.time < chain.max_time - 0.5 * sim.dt:
            sim.run(until=min(sim.time + 0.05, chain.max_time))
            if sim.time - sim.rec.last_onset[0] >= quiet:
                break
    except (RuntimeError, ValueError, FloatingPointError) as err:
        return None, str(err).splitlines()[0], np.nan
    return sim, time.process_time() - t0, e0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_chain_arguments(parser, n=20)
    parser.add_argument("--quiet", type=float, default=0.2, help="end: no onset for [s]")
    parser.add_argument("--safety", type=float, nargs="+", default=[0.02, 0.05, 0.1, 0.2, 0.4])
    args = parser.parse_args()
    params = chain_params(args, held=True)
    chain = DominoChain(params, safety=1.0)  # (the step is set per run below)
    n = np.arange(1, args.n)
    reference = None
    print(
        "| safety | dt [s] | steps | CPU [s] | reached | arrival at the last [s] | "
        "max abs diff [s] | max rel diff | front speed [m/s] | dissipated [J] | "
        "total energy drift (relative) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for safety in sorted(args.safety):
        chain = DominoChain(params, safety=min(safety, 1.0))
        sim, cpu, e0 = run_to_end(chain, safety, args.quiet)
        if sim is None:
            print(f"| {safety} | {safety * chain.dt / min(safety, 1.0):.3e} | unstable: {cpu} |")
            continue
        arrival = sim.rec.first_contact[n - 1, n]
        if reference is None:
            reference = arrival
        both = np.isfinite(arrival) & np.isfinite(reference)
        diff = np.abs(arrival - reference)[both]
        rel = diff / reference[both]
        tail = np.isfinite(arrival) & (n >= args.n // 2)
        speed = np.polyfit(arrival[tail], chain.positions[n[tail]], 1)[0]
        energy = sim.energy()
        dissipated = sum(v for k, v in energy.items() if k.startswith("dissipated"))
        drift = (energy["total"] - e0) / e0
        last = int(n[np.isfinite(arrival)][-1])
        print(
            f"| {safety} | {sim.dt:.3e} | {int(sim.rec.step[0])} | {cpu:.1f} | {reached(sim)} | "
            f"{arrival[last - 1]:.6f} | {diff.max():.2e} | {rel.max():.2e} | {speed:.5f} | "
            f"{dissipated:.5e} | {drift:.2e} |",
            flush=True,
        )


if __name__ == "__main__":
    main()

"""Wall time of the rod model: 1000 dominoes, d/l = 0.4, k/k* = 1e4, until the wave passed.

Run: ``python benchmarks/bench_rods.py [--repeat 5] [--n 1000]``. Single thread (numba
kernels are serial). The first call compiles (or loads the numba cache) and is not
timed; the medians of the wall and CPU (process) time of ``--repeat`` runs are reported
per contact normal (CPU time is the fairer number on a shared machine).
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np

from dominowave.chain.theory_vs_rods import paper_chain
from dominowave.rods import simulate


def bench(n: int, normal: str, repeat: int, steps_per_contact: float) -> dict:
    """Median wall time [s] of ``repeat`` runs and what the run did."""
    chain = paper_chain(0.4, 1e4, n, normal=normal)  # l = m = 1 m, kg; g = 9.81
    push = 7.3  # ~ the EJ limit Omega (eq 9) at d/l = 0.4 [rad/s]
    simulate(paper_chain(0.4, 1e4, 3, normal=normal), push=push)  # compile / load cache
    times, cpu = [], []
    for _ in range(repeat):
        start, start_cpu = time.perf_counter(), time.process_time()
        run = simulate(chain, push=push, steps_per_contact=steps_per_contact)
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    # energy ledger: kinetic + gravity + elastic + dissipated + lost at the floor
    ledger = run.total_energy + run.samples[:, 4] + run.samples[:, 5]
    return {
        "normal": normal,
        "median_s": statistics.median(times),
        "cpu_s": statistics.median(cpu),
        "status": run.status,
        "steps": run.n_steps,
        "simulated_s": run.t_end,
        "reached": int(np.sum(np.isfinite(run.arrival))),
        "energy_drift": float(np.max(np.abs(ledger - ledger[0])) / ledger[0]),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--steps-per-contact", type=float, default=100.0)
    args = parser.parse_args()
    print(f"# {platform.processor() or platform.machine()}, Python {platform.python_version()}")
    print("normal     wall[s]  cpu[s]  status       steps    t_sim[s]  reached  ledger drift/E0")
    for normal in ("geometric", "head-on"):
        r = bench(args.n, normal, args.repeat, args.steps_per_contact)
        print(
            f"{r['normal']:<10} {r['median_s']:7.3f} {r['cpu_s']:7.3f}  {r['status']:<12} "
            f"{r['steps']:7d} {r['simulated_s']:9.3f} {r['reached']:8d}  {r['energy_drift']:.1e}"
        )


if __name__ == "__main__":
    main()

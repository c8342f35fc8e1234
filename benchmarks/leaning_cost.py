"""Cost of the leaning-train theory (``dominowave.theory.leaning``): one steady state, a
vector of frictions, and a transient from a push, for the standard domino.

Each is timed ``--repeat`` times after one warm-up call (NumPy, no compilation); the
median wall time is printed.

Usage::

    python benchmarks/leaning_cost.py [--repeat 7]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from dominowave.theory import leaning

L, S, GAP = 0.048, 0.0075, 0.00938  # the standard domino at the films' gap [m]


def median_wall(call, repeat: int) -> float:
    """Median wall time [s] of ``call()`` over ``repeat`` runs after a warm-up."""
    call()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=7, help="timed runs of each")
    args = parser.parse_args()
    frictions = np.linspace(0.2, 0.75, 256)
    cases = {
        "limit_speed, one point (friction 0.3)": lambda: leaning.limit_speed(
            height=L, thickness=S, gap=GAP, friction=0.3
        ),
        "limit_speed, 256 frictions": lambda: leaning.limit_speed(
            height=L, thickness=S, gap=GAP, friction=frictions
        ),
        "transient, 40 dominoes": lambda: leaning.transient(L, S, GAP, 0.3, n_dominoes=40),
    }
    print(f"| case | wall [s], median of {args.repeat} |")
    print("| --- | --- |")
    for name, call in cases.items():
        print(f"| {name} | {median_wall(call, args.repeat):.3g} |")


if __name__ == "__main__":
    main()

"""The step of a softened chain: how far the front speed moves as the step grows.

A chain of given materials runs with the softest contact spring within its tolerance
(``chain.fidelity``), and with the step ``T_c / n`` (``DominoChain``'s
``steps_per_collision``). This script runs each chain of the fidelity validation
(``fidelity_validation.CHAINS`` and ``LENGTHS``: standard dominoes on hardwood, 3D) at
the spring of the default tolerance with ``n`` = 50, 20, 15 and 10, and gives the front
speed fitted from domino ``fit_from`` on, its relative change from ``n`` = 50, the step
and the wall time (warm kernels; one warm-up run first). The largest change at each
step is ``chain.fidelity.STEP_EFFECTS``, from which a softened chain's step is chosen
(``chain.fidelity.steps_per_collision``).

Usage::

    cd docs/real_dominoes && python step_convergence.py --out step_convergence.csv
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from fidelity_validation import (  # this folder's validation chains
    CHAINS,
    chain_columns,
    chain_params,
    measure,
)

from dominowave.chain import DominoChain
from dominowave.chain.wave import speed_from

STEPS = (50, 20, 15, 10)
"""Steps per collision time, the first the reference."""


def rows_of(gap, friction, restitution, floor_restitution, n, fit_from) -> list[dict]:
    """One row per number of steps of the chain at the default tolerance's spring."""
    p = chain_params(gap, friction, restitution, floor_restitution, n)
    rows, reference = [], None
    for steps in STEPS:
        chain = DominoChain(p, steps_per_collision=steps)
        start = time.perf_counter()
        run = chain.run()
        wall = time.perf_counter() - start
        speed = speed_from(run.arrival, run.positions, fit_from).speed
        reference = speed if reference is None else reference
        rows.append(
            {
                **chain_columns(gap, friction, restitution, floor_restitution, n, fit_from),
                "k_over_kstar": f"{chain.params.stiffness_over_kstar:.4g}",
                "steps_per_collision": steps,
                "dt_s": f"{run.dt:.4g}",
                "speed_m_s": f"{speed:.5f}",
                "change_from_50": f"{speed / reference - 1.0:+.5f}",
                "wall_s": f"{wall:.3g}",
            }
        )
        print(rows[-1], flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV to write")
    measure(rows_of, CHAINS, parser.parse_args().out)


if __name__ == "__main__":
    main()

"""The softened contact of a chain of given materials against the plastic's own.

A chain of standard dominoes (``chain.presets.standard_domino``, hardwood floor) runs by
default with the softest contact spring whose estimated speed error stays within 2 %
(``chain.fidelity``). This script measures that error: each chain of :data:`CHAINS` is
run at the plastic's stiffness (``fidelity="exact"``) and at each tolerance of
:data:`TOLERANCES`, and each row gives the front speed fitted from domino ``fit_from``
on (pitch-based, ``chain.wave.speed_from``), the measured relative change of that speed
from the exact run (the softened chains at their own step,
``chain.fidelity.steps_per_collision``: T_c/20 at 1 %, T_c/10 at 2 % and 5 %; the exact
ones and the nearly elastic ones at T_c/50), the estimate (``ContactFidelity.error_at`` at the
run's own speed), the spring's ``k/k*``, the time step and the wall time of the run
(warm kernels; one warm-up run first). The chains: 12 dominoes fitted from domino 3
(as ``predict``), and 30 fitted from domino 10 (as the films), 3D; the tests run the
same chains (``tests/chain/test_fidelity.py``).

Usage::

    cd docs/real_dominoes && python fidelity_validation.py --out fidelity_validation.csv
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from rows_csv import write_rows  # this folder's CSV writer

from dominowave.chain import DominoChain
from dominowave.chain.fidelity import choose_contact, steps_per_collision
from dominowave.chain.presets import standard_domino
from dominowave.chain.wave import speed_from

CHAINS = [
    (0.00938, 0.3, 0.5, 0.5),
    (0.00938, 0.0, 0.5, 0.5),
    (0.01509, 0.525, 0.1, 0.5),
    (0.005, 0.3, 0.5, 0.5),
]
"""(gap [m], friction between dominoes, restitution between dominoes, with the floor) of
each chain the setting softens."""
NEARLY_ELASTIC = [
    (0.00938, 0.2, 0.9, 0.5),
    (0.00938, 0.2, 0.5, 0.9),
]
"""Chains with a restitution above ``chain.fidelity.MAX_RESTITUTION``, which keep the
material's spring: run here at the spring the tolerance gives the same chain at
restitution 0.5 (the estimate does not depend on it), to show why."""
TOLERANCES = ("exact", 0.01, 0.02, 0.05)
LENGTHS = ((12, 3), (30, 10))
"""(dominoes, fitted from domino) of the chains."""


def chain_params(gap, friction, restitution, floor_restitution, n):
    """The standard chain of ``n`` dominoes (3D, hardwood) of one entry of :data:`CHAINS`."""
    return standard_domino(
        gap=gap,
        floor="hardwood",
        n_dominoes=n,
        friction_dominoes=friction,
        restitution_dominoes=restitution,
        restitution_floor=floor_restitution,
    )


def chain_columns(gap, friction, restitution, floor_restitution, n, fit_from) -> dict:
    """The CSV columns that name a chain of :data:`CHAINS` and its fit."""
    return {
        "gap_m": gap,
        "friction_dominoes": friction,
        "restitution_dominoes": restitution,
        "restitution_floor": floor_restitution,
        "n_dominoes": n,
        "fit_from": fit_from,
    }


def rows_of(gap, friction, restitution, floor_restitution, n, fit_from) -> list[dict]:
    """One row per tolerance of the chain (3D, hardwood)."""
    p = chain_params(gap, friction, restitution, floor_restitution, n)
    # the chain at restitution 0.5 or below, whose spring a tolerance softens
    twin = p.with_(
        restitution_dominoes=min(restitution, 0.5), restitution_floor=min(floor_restitution, 0.5)
    )
    rows, exact = [], None
    for tolerance in TOLERANCES:
        contact = choose_contact(twin, tolerance)
        if contact.softened:  # the spring and the step the setting gives the chain (the
            # nearly elastic ones, which it does not soften: the spring alone)
            steps = steps_per_collision(contact) if twin == p else None
            chain = DominoChain(p.with_(kn=contact.kn), steps_per_collision=steps)
        else:
            chain = DominoChain(p, fidelity="exact")
        start = time.perf_counter()
        run = chain.run()
        wall = time.perf_counter() - start
        speed = speed_from(run.arrival, run.positions, fit_from).speed
        exact = speed if tolerance == "exact" else exact
        rows.append(
            {
                **chain_columns(gap, friction, restitution, floor_restitution, n, fit_from),
                "fidelity": tolerance,
                "softened_by_default": twin == p,
                "k_over_kstar": f"{chain.params.stiffness_over_kstar:.4g}",
                "dt_s": f"{run.dt:.4g}",
                "speed_m_s": f"{speed:.5f}",
                "error_measured": f"{abs(speed / exact - 1.0):.5f}",
                "error_estimated": f"{contact.error_at(speed):.5f}",
                "wall_s": f"{wall:.3g}",
            }
        )
        print(rows[-1], flush=True)
    return rows


def measure(rows_of, chains, out: Path) -> None:
    """Warm the kernels, then write to ``out`` the rows ``rows_of(*values, n, fit_from)``
    of each chain ``values`` of ``chains`` at each length of :data:`LENGTHS`."""
    DominoChain(standard_domino(gap=0.00938, floor="hardwood", n_dominoes=4)).run()
    rows = []
    for n, fit_from in LENGTHS:
        for values in chains:
            rows += rows_of(*values, n, fit_from)
    write_rows(out, rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV to write")
    measure(rows_of, CHAINS + NEARLY_ELASTIC, parser.parse_args().out)


if __name__ == "__main__":
    main()

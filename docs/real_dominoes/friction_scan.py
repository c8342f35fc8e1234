"""The standard domino's front speed against the friction between dominoes.

For the standard 48 x 24 x 7.5 mm box domino (``chain.presets.standard_domino``, the
plastic's contact stiffness, ``fidelity="exact"``, and every box free and awake,
``held=False``, ``sleep=False``, as the shipped scan was measured, every other value
nominal from materials.toml) at the 9.38 mm gap of the Smarter Every Day films, a chain
of ``--n`` dominoes pushed with ``omega = sqrt(g/l)`` is run once per (model, floor,
domino-domino friction), and its front speed fitted from domino ``--fit-from`` on,
pitch-based (``chain.wave.speed_from``), as the films are fitted. The friction values go
below the range of materials.toml on purpose: the scan asks how low the friction would
have to be for the model to run as fast as the films, it fits nothing.

Usage::

    python docs/real_dominoes/friction_scan.py --out src/dominowave/chain/data/dem_friction_scan.csv

The package ships the result (``dominowave.chain.reconcile`` reads it to infer the
friction at which the DEM matches a measurement).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

from rows_csv import write_rows  # this folder's CSV writer

from dominowave.chain.build import chain_positions
from dominowave.chain.presets import standard_domino
from dominowave.chain.scenario import DominoChain, Push
from dominowave.chain.wave import speed_from

FRICTIONS = (0.0, 0.1, 0.2, 0.3, 0.525)
"""Domino-domino friction coefficients scanned (0.525: the nominal of materials.toml)."""


def front_speed(model: str, floor: str, friction: float, n: int, fit_from: int, gap: float):
    """Fitted front speed [m/s], its uncertainty (``SteadySpeed.speed_err``) [m/s] and the
    CPU time [s] of one chain."""
    p = standard_domino(
        gap=gap, floor=floor, n_dominoes=n, model=model, friction_dominoes=friction, held=False
    )
    start = time.process_time()
    run = DominoChain(p, fidelity="exact", sleep=False).run(Push(omega=math.sqrt(p.g / p.height)))
    fit = speed_from(run.arrival, chain_positions(p), fit_from)
    return fit.speed, fit.speed_err, time.process_time() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV file to write")
    parser.add_argument("--n", type=int, default=30, help="dominoes per chain")
    parser.add_argument("--fit-from", type=int, default=10, help="first fitted domino")
    parser.add_argument("--gap", type=float, default=0.00938, help="clear gap d [m]")
    parser.add_argument("--models", default="2d,3d", help="comma-separated: 2d, 3d")
    parser.add_argument("--floors", default="felt,hardwood", help="comma-separated floors")
    args = parser.parse_args()
    rows = []
    for model in args.models.split(","):
        for floor in args.floors.split(","):
            for friction in FRICTIONS:
                v, se, cpu = front_speed(model, floor, friction, args.n, args.fit_from, args.gap)
                rows.append(
                    {
                        "model": model,
                        "floor": floor,
                        "gap_m": args.gap,
                        "friction_dominoes": friction,
                        "speed_m_s": f"{v:.4f}",
                        "speed_stderr_m_s": f"{se:.4f}",
                        "cpu_s": f"{cpu:.0f}",
                    }
                )
                print(rows[-1], flush=True)
    write_rows(args.out, rows)


if __name__ == "__main__":
    main()

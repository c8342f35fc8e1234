"""One effective friction from one filmed condition, tested on the conditions it has not seen.

The friction between dominoes is the value that decides a real chain's speed, and none
was measured on dominoes. This script infers one *effective* friction from a single
filmed condition (``--fit-gap``, ``--fit-floor``: by default 9.38 mm on hardwood, the
seven rows of Smarter Every Day 178) and predicts every other filmed condition with it,
never using a predicted row in the fit:

* the leaning train (``theory.leaning``): the friction at which its steady speed is the
  fitted condition's mean speed (``chain.reconcile.leaning_friction_for_speed``), then
  its steady speed at each other gap (the train has no floor: both floors get the same);
* the box DEM: the friction interpolated in the shipped friction scan
  (``chain.reconcile.dem_friction_for_speed``, 3D, the fitted floor), then a chain of
  ``--n`` standard dominoes at each other condition with that friction, the plastic's
  contact stiffness (``fidelity="exact"``) and every box free and awake (``held=False``,
  ``sleep=False``), as the shipped scan, and every other value
  nominal, fitted from domino ``--fit-from`` on, pitch-based, as the films are.

Writes one CSV row per condition: the measured mean, each model's prediction and its
error in %. Usage::

    nice python docs/real_dominoes/calibration.py --out docs/real_dominoes/calibration.csv
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

from rows_csv import write_rows  # this folder's CSV writer

from dominowave.chain.build import chain_positions
from dominowave.chain.presets import standard_domino
from dominowave.chain.reconcile import (
    compare_with_measurements,
    dem_friction_for_speed,
    leaning_friction_for_speed,
)
from dominowave.chain.scenario import DominoChain, Push
from dominowave.chain.wave import speed_from
from dominowave.theory import leaning

HEIGHT, THICKNESS = 0.048, 0.0075  # the standard domino [m] (the films' height assumed)
CONDITIONS = (  # (gap [m], floor) of every filmed asymptotic speed
    (0.00938, "hardwood"),
    (0.00938, "felt"),
    (0.008959989562, "hardwood"),
    (0.0150876, "hardwood"),
    (0.0432562, "hardwood"),
)


def dem_speed(gap: float, floor: str, friction: float, n: int, fit_from: int) -> float:
    """The 3D box chain's front speed [m/s] at this friction between dominoes."""
    p = standard_domino(gap=gap, floor=floor, n_dominoes=n, friction_dominoes=friction, held=False)
    run = DominoChain(p, fidelity="exact", sleep=False).run(Push(omega=math.sqrt(p.g / p.height)))
    fit = speed_from(run.arrival, chain_positions(p), fit_from)
    return fit.speed if fit.settled else math.nan


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV file to write")
    parser.add_argument("--fit-gap", type=float, default=0.00938, help="fitted gap [m]")
    parser.add_argument("--fit-floor", default="hardwood", help="fitted floor")
    parser.add_argument("--n", type=int, default=30, help="dominoes per DEM chain")
    parser.add_argument("--fit-from", type=int, default=10, help="first fitted domino")
    args = parser.parse_args()
    fitted = compare_with_measurements(args.fit_gap, args.fit_floor)
    mu_lean, _ = leaning_friction_for_speed(
        fitted.mean, height=HEIGHT, thickness=THICKNESS, gap=args.fit_gap
    )
    mu_dem, _ = dem_friction_for_speed(fitted.mean, gap=args.fit_gap, floor=args.fit_floor)
    print(f"fitted on {args.fit_floor} {1e3 * args.fit_gap:.2f} mm ({fitted.mean:.4f} m/s):")
    print(f"  leaning train friction {mu_lean:.4f}, box DEM friction {mu_dem:.4f}")
    rows = []
    for gap, floor in CONDITIONS:
        films = compare_with_measurements(gap, floor)
        role = "fit" if (gap, floor) == (args.fit_gap, args.fit_floor) else "predicted"
        lean = leaning.limit_speed(height=HEIGHT, thickness=THICKNESS, gap=gap, friction=mu_lean)
        start = time.process_time()
        dem = dem_speed(gap, floor, mu_dem, args.n, args.fit_from)
        rows.append(
            {
                "gap_m": gap,
                "floor": floor,
                "role": role,
                "films": len(films.rows),
                "measured_m_s": round(films.mean, 4),
                "leaning_friction": round(mu_lean, 4),
                "leaning_m_s": round(float(lean), 4),
                "leaning_error_pct": round(100 * (lean / films.mean - 1), 1),
                "dem_friction": round(mu_dem, 4),
                "dem_m_s": round(dem, 4),
                "dem_error_pct": round(100 * (dem / films.mean - 1), 1),
                "dem_cpu_s": round(time.process_time() - start),
            }
        )
        print(rows[-1], flush=True)
    write_rows(args.out, rows)


if __name__ == "__main__":
    main()

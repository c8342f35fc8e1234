"""The leaning train beside the box DEM and MuJoCo, chain for chain.

Reads the box DEM runs of ``leaning_vs_dem.py`` (``--dem``: restitution 0.01, floor
friction 1, 30 dominoes) and the MuJoCo runs of ``benchmarks/mujoco_chain.py``
(``--mujoco``: exact boxes, 2 ms contacts, the same grid), and computes the leaning
train (``theory.leaning``) at each (gap, friction between dominoes): its steady speed and
the speed a 30-domino train pushed with ``sqrt(g/l)`` gives when fitted from domino 10,
pitch-based, as the codes' chains are (``chain.wave.speed_from``). Writes one CSV row
per (gap, friction) with every code's speed and its difference from the train's fit.

Usage::

    python docs/real_dominoes/leaning_codes.py --out docs/real_dominoes/leaning_codes.csv
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np
from rows_csv import write_rows  # this folder's CSV writer

from dominowave.chain.wave import speed_from
from dominowave.theory import leaning

HEIGHT, THICKNESS = 0.048, 0.0075  # the standard domino [m]


def train_fit(gap: float, friction: float, n: int, fit_from: int) -> float:
    """Front speed [m/s] of an ``n``-domino train from a push, fitted from ``fit_from``."""
    tr = leaning.transient(HEIGHT, THICKNESS, gap, friction, n_dominoes=n)
    arrival = np.concatenate([[0.0], tr.hit_times])
    return speed_from(arrival, np.arange(n) * (gap + THICKNESS), fit_from).speed


def _read(path: Path) -> list[dict]:
    with path.open() as f:
        return list(csv.DictReader(f))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV file to write")
    here = Path(__file__).parent
    parser.add_argument("--dem", type=Path, default=here / "leaning_vs_dem.csv")
    parser.add_argument(
        "--mujoco", type=Path, default=here.parent.parent / "benchmarks" / "mujoco_chain.csv"
    )
    args = parser.parse_args()
    dem = {
        (r["model"], float(r["gap_m"]), float(r["friction_dominoes"])): r for r in _read(args.dem)
    }
    mujoco = {
        (float(r["gap_m"]), float(r["friction_dominoes"])): float(r["speed_m_s"])
        for r in _read(args.mujoco)
        if float(r["friction_floor"]) == 1.0 and int(r["n"]) == 30
    }  # the last row of a (gap, friction) wins: the grid's dt (the dt series repeats one)
    rows = []
    for (model, gap, mu), r in sorted(dem.items()):
        if model != "3d":
            continue
        fit = train_fit(gap, mu, 30, 10)
        limit = float(leaning.limit_speed(height=HEIGHT, thickness=THICKNESS, gap=gap, friction=mu))
        row = {
            "gap_m": gap,
            "friction_dominoes": mu,
            "leaning_limit_m_s": round(limit, 4),
            "leaning_fit_m_s": round(fit, 4),
            "dem_2d_m_s": float(dem[("2d", gap, mu)]["speed_m_s"]),
            "dem_3d_m_s": float(r["speed_m_s"]),
            "mujoco_m_s": round(mujoco.get((gap, mu), float("nan")), 4),
        }
        for code in ("dem_2d", "dem_3d", "mujoco"):
            row[f"{code}_vs_leaning_pct"] = round(100 * (row[f"{code}_m_s"] / fit - 1), 1)
        rows.append(row)
        print(row, flush=True)
    write_rows(args.out, rows)


if __name__ == "__main__":
    main()

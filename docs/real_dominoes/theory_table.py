"""Regenerate the theory-vs-measurement table of docs/real_dominoes.md.

For every published measurement in the package's measurements.csv: the paper's eq 34 in
the rigid limit (T_c = 0, Efthimiou-Johnson free fall of thin dominoes of the measured
height, times (d + s) / d) and the % difference (theory - measured) / measured. Rows whose
source does not publish the domino's height or thickness get "n/a".

    python docs/real_dominoes/theory_table.py                 # print the Markdown table
    python docs/real_dominoes/theory_table.py --csv out.csv   # also write it as CSV
    python docs/real_dominoes/theory_table.py --measurements my.csv
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

from dominowave.chain.measurements import eq34_rigid_speed, load_measurements

COLUMNS = ("key", "l_m", "s_m", "gap_m", "basis", "measured_m_s", "kind", "eq34_m_s", "diff_pct")


def rows(measurements_path: str | None = None) -> list[dict[str, str]]:
    """One row of strings per measurement (units in the column names)."""
    out = []
    for m in load_measurements(measurements_path):
        v = eq34_rigid_speed(m)

        def fmt(x, spec):
            return "n/a" if x is None else format(x, spec)

        out.append(
            {
                "key": m.key,
                "l_m": fmt(m.height, ".4g"),
                "s_m": fmt(m.thickness, ".4g"),
                "gap_m": fmt(m.gap, ".4g"),
                "basis": m.spacing_basis,
                "measured_m_s": format(m.speed, ".3g"),
                "kind": m.speed_kind,
                "eq34_m_s": fmt(v, ".3g"),
                "diff_pct": fmt(None if v is None else 100.0 * (v - m.speed) / m.speed, "+.0f"),
            }
        )
    return out


def markdown(table: list[dict[str, str]]) -> str:
    head = "| " + " | ".join(COLUMNS) + " |"
    rule = "|" + "---|" * len(COLUMNS)
    body = ["| " + " | ".join(r[c] for c in COLUMNS) + " |" for r in table]
    return "\n".join([head, rule, *body])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--measurements", help="a measurements CSV (default: the shipped one)")
    parser.add_argument("--csv", type=Path, help="also write the table to this CSV file")
    args = parser.parse_args(argv)
    table = rows(args.measurements)
    if args.csv:
        with args.csv.open("w", encoding="utf-8", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=COLUMNS)
            writer.writeheader()
            writer.writerows(table)
    print(markdown(table))
    return 0


if __name__ == "__main__":
    sys.exit(main())

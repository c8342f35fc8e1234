"""Draw Fig 6B-E with clump dominoes beside box dominoes, and print the box tables.

Reads the clump summary ``docs/fig6/summary.csv`` and the box summary
``docs/fig6/box/summary.csv`` (``dominowave paper-fig6 --shape box --out DIR``) and
writes ``fig6B..E_beside.png/.csv`` into ``docs/fig6/box/``. Speeds in the tables are
``v / sqrt(g l)``: mean +- standard error over the members that settled (their count
when not all did; a member that failed counts as not settled).

Run: ``python docs/fig6/box/beside.py``
"""

from __future__ import annotations

from pathlib import Path

from dominowave.chain.build import ChainParams
from dominowave.plots.fig6 import plot_fig6_beside
from dominowave.sweep.fig6 import read_rows
from dominowave.units import speed_scale

HERE = Path(__file__).resolve().parent


def _summary(path: Path) -> list[dict]:
    rows = []
    for r in read_rows(path):
        rows.append({k: (v if k in ("config", "shape") else float(v)) for k, v in r.items()})
    return rows


def _cell(r: dict, scale: float, members: int) -> str:
    """The cell of one ensemble of ``members`` runs (a member that failed -- its
    failure.json in the study folder -- is missing from ``r['members']``)."""
    if r["n_settled"] == 0:
        return f"- (0/{members})"
    text = f"{r['speed_mean'] / scale:.2f}"
    if r["n_settled"] > 1:
        text += f" +- {r['speed_stderr'] / scale:.2f}"
    if r["n_settled"] < members:
        text += f" ({r['n_settled']:.0f}/{members})"
    return text


def main() -> None:
    clump = _summary(HERE.parent / "summary.csv")
    box = _summary(HERE / "summary.csv")
    plot_fig6_beside(clump, box, HERE)
    p = ChainParams()
    scale = float(speed_scale(p.height, p.g))
    configs = ("2d", "3d", "3d_asym", "k1e3", "k1e5", "damp_small", "damp_large", "mu0.6")
    print("| d/l | " + " | ".join(configs) + " |")
    print("|" + " --- |" * (len(configs) + 1))
    table = {(r["config"], r["d_over_l"]): r for r in box}
    members = int(max(r["members"] for r in box))
    for d in sorted({r["d_over_l"] for r in box}):
        cells = [_cell(table[(c, d)], scale, members) for c in configs]
        print(f"| {d:.1f} | " + " | ".join(cells) + " |")
    print()
    print(
        "| d/l | eq 34 box | transient, same dominoes | multiple-hit pairs | base slip | mech. II |"
    )
    print("| --- | --- | --- | --- | --- | --- |")
    for d in sorted({r["d_over_l"] for r in box}):
        r = table[("2d", d)]
        print(
            f"| {d:.1f} | {r['theory_speed'] / scale:.2f} | "
            f"{r['theory_window_speed'] / scale:.2f} | "
            f"{100 * r['multiple_collision_fraction']:.0f} % | "
            f"{100 * r['mean_abs_slip']:.1f} cm | {100 * r['forward_slip_fraction']:.0f} % |"
        )


if __name__ == "__main__":
    main()

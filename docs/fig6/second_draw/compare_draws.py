"""Compare two draws of the full Fig 6 sweep: docs/fig6/summary.csv (engine of commit
e28b52c) and docs/fig6/second_draw/summary.csv (the engine since commit 3448782, whose
floating-point results differ at round-off, so every chaotic member is a new draw).
Prints the statistics of the differences and the comparisons that docs/fig6.md draws
conclusions from.

Run from the repository root:  python docs/fig6/second_draw/compare_draws.py
"""

import csv
import math
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SQRT_GL = math.sqrt(9.81 * 0.05)  # speeds in the tables are v / sqrt(g l), l = 5 cm
SPACINGS = ["0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8"]


def load(path):
    return {(r["config"], r["d_over_l"]): r for r in csv.DictReader(open(path))}


old, new = load(HERE.parent / "summary.csv"), load(HERE / "summary.csv")


def speed(table, config, d):
    r = table[(config, d)]
    return float(r["speed_mean"]) / SQRT_GL, float(r["speed_stderr"]) / SQRT_GL, r["n_settled"]


rel, z, beyond = [], [], []
for key in old:
    (mo, so, _), (mn, sn, _) = speed(old, *key), speed(new, *key)
    if math.isfinite(so) and math.isfinite(sn):
        rel.append(mn / mo - 1.0)
        z.append((mn - mo) / math.hypot(so, sn))
        if abs(z[-1]) > 2.0:
            beyond.append(f"{key[0]} d/l={key[1]}: {mo:.2f} -> {mn:.2f} ({z[-1]:+.1f})")
rel, z = np.array(rel), np.array(z)
print(
    f"{len(z)} entries with a standard error in both draws: mean difference "
    f"{100 * rel.mean():+.1f} %, median {100 * np.median(rel):+.1f} %, rms "
    f"{np.sqrt(np.mean(z**2)):.2f} combined standard errors; beyond 2: {beyond}"
)
for name, a, b in [
    ("2D vs symmetric 3D", "2d", "3d"),
    ("2D vs 3D with asymmetry", "2d", "3d_asym"),
    ("2D vs damping 0.02", "2d", "damp_small"),
    ("2D vs damping 0.1", "2d", "damp_large"),
    ("2D vs phi_f = 0.6", "2d", "mu0.6"),
]:
    print(name + " (second draw):")
    for d in SPACINGS:
        (ma, sa, na), (mb, sb, nb) = speed(new, a, d), speed(new, b, d)
        print(
            f"  d/l {d}: {ma:.2f} +- {sa:.2f} ({na}) vs {mb:.2f} +- {sb:.2f} ({nb}): "
            f"{100 * (mb / ma - 1):+.0f} %, {(mb - ma) / math.hypot(sa, sb):+.1f} s.e."
        )
print("stiffness k/k* = 1e3 / 1e4 / 1e5 (second draw):")
for d in SPACINGS:
    print(f"  d/l {d}: " + " / ".join(f"{speed(new, c, d)[0]:.2f}" for c in ("k1e3", "2d", "k1e5")))

"""Box dominoes against the paper's clump dominoes on the chain of docs/fig6.md.

For each model (2d, 3d, 3d with lateral asymmetry 0.02) and d/l, an ensemble of seeded
perturbed pushes (``DominoChain.ensemble``, seed 0, jitter 1e-3) of the clump chain (the
paper's base configuration, ``ChainParams`` defaults) and of the box chain of the same
l, s, w, density, k/k*, phi_f, phi_d (``shape = "box"``, rounding s/20, not held).
Besides the settled-region fit (``speed``, members whose wave settled), the mean speed over
the last ``TAIL`` pitches of every member that reached the end (``tail_speed``): short
chains at small d/l rarely settle (docs/fig6.md), the tail speed is defined for all.
Writes ``box_vs_clump.csv`` beside this file (or to the path given) and prints it.

``--standard``: the common 48 x 24 x 7.5 mm domino (l, w, s) instead of the paper's
5 x 2.5 x 0.5 cm one (every other parameter as above; its clump has round(l/s) = 6 spheres
per column).

Run: ``python docs/shape/box_vs_clump.py [--members 8] [--d-over-l 0.2,0.4,0.6]
[--models 2d,3d,3d_asym] [--standard] [--out CSV]``
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from tail_speed import mean_and_stderr, tail_speeds, write_rows

from dominowave.chain import ChainParams, DominoChain

STANDARD = {"height": 0.048, "width": 0.024, "thickness": 0.0075}
"""The common toppling domino's outer size [m]."""

MODELS = {"2d": {}, "3d": {"model": "3d"}, "3d_asym": {"model": "3d", "lateral_asymmetry": 0.02}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--members", type=int, default=8)
    ap.add_argument("--d-over-l", default="0.2,0.4,0.6")
    ap.add_argument("--models", default=",".join(MODELS))
    ap.add_argument("--standard", action="store_true", help="48 x 24 x 7.5 mm dominoes")
    ap.add_argument("--out", type=Path, default=Path(__file__).with_name("box_vs_clump.csv"))
    args = ap.parse_args()
    rows = []
    for model in args.models.split(","):
        for d in (float(x) for x in args.d_over_l.split(",")):
            for shape in ("clump", "box"):
                size = STANDARD if args.standard else {}
                p = ChainParams(
                    d_over_l=d, shape=shape, held=shape == "clump", **size, **MODELS[model]
                )
                start = time.perf_counter()
                ens = DominoChain(p, sleep=False).ensemble(members=args.members, seed=0)
                settled = [r.wave.settled for r in ens.runs]
                tail = tail_speeds(ens, p.pitch)
                tail_mean, tail_stderr = mean_and_stderr(tail)
                rows.append(
                    {
                        "model": model,
                        "height": p.height,
                        "d_over_l": d,
                        "shape": shape,
                        "members": args.members,
                        "n_settled": int(np.sum(settled)),
                        "reached_all": int(sum(r.reached_all for r in ens.runs)),
                        "speed": ens.speed.mean,
                        "speed_stderr": ens.speed.stderr,
                        "tail_speed": tail_mean,
                        "tail_speed_stderr": tail_stderr,
                        "theory_speed": ens.theory_speed,
                        "mass": p.mass,
                        "kn": p.contact_stiffness,
                        "wall_time": time.perf_counter() - start,
                    }
                )
                print(rows[-1], flush=True)
    write_rows(args.out, rows)


if __name__ == "__main__":
    main()

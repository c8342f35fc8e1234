"""The paper's Fig 6 trends (stiffness, damping, floor friction) with box dominoes.

Each 2D configuration of ``dominowave.chain.paper_fig6.CONFIGS`` at one d/l, as clumps
(the paper's model) and as boxes (``shape = "box"``), ensembles of seeded perturbed
pushes (seed 0, jitter 1e-3): the fitted speed over the members that settled and the
mean speed over the last ``TAIL`` pitches. Writes a CSV and prints it.

Run: ``python docs/shape/trends.py [--members 2] [--d-over-l 0.4] --out CSV``
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from tail_speed import mean_and_stderr, tail_speeds, write_rows

from dominowave.chain import DominoChain
from dominowave.chain.paper_fig6 import CONFIGS, fig6_params

PLANAR = ("2d", "k1e3", "k1e5", "damp_small", "damp_large", "mu0.6")
"""The 2D configurations of Fig 6 (the 3D ones are ``3d`` and ``3d_asym``)."""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--members", type=int, default=2)
    ap.add_argument("--d-over-l", type=float, default=0.4)
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    rows = []
    for config in PLANAR:
        assert config in CONFIGS
        for shape in ("clump", "box"):
            p = fig6_params(config, args.d_over_l, n_dominoes=30).with_(shape=shape)
            if shape == "box":
                p = p.with_(held=None)  # a box stands by itself
            start = time.perf_counter()
            ens = DominoChain(p).ensemble(members=args.members, seed=0)
            tail = tail_speeds(ens, p.pitch)
            tail_mean, tail_stderr = mean_and_stderr(tail)
            rows.append(
                {
                    "config": config,
                    "shape": shape,
                    "d_over_l": args.d_over_l,
                    "members": args.members,
                    "n_settled": ens.speed.n,
                    "reached_all": tail.size,
                    "speed": ens.speed.mean,
                    "speed_stderr": ens.speed.stderr,
                    "tail_speed": tail_mean,
                    "tail_speed_stderr": tail_stderr,
                    "wall_time": time.perf_counter() - start,
                }
            )
            print(rows[-1], flush=True)
    write_rows(args.out, rows)


if __name__ == "__main__":
    main()

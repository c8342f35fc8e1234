"""Does the symmetric 3D box chain of Fig 6 stay in its plane?  Per member: the speed, the
first time any domino's centre is more than 1 um off the chain's plane (y = 0), and the
largest |y| over the run.

Run: ``python docs/fig6/box/planarity.py [--d-over-l 0.4] [--members 0 1 2 3]``
"""

from __future__ import annotations

import argparse

import numpy as np

from dominowave.chain import DominoChain
from dominowave.chain.paper_fig6 import fig6_params
from dominowave.chain.scenario import member_push_factor


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--d-over-l", type=float, default=0.4)
    ap.add_argument("--members", type=int, nargs="+", default=[0, 1, 2, 3])
    args = ap.parse_args()
    for m in args.members:  # (the preset's members: seed 0, jitter 1e-3)
        chain = DominoChain(fig6_params("3d", args.d_over_l, 30, "box"))
        push = chain.resolve(None).scaled(member_push_factor(0, m, 1e-3))
        run = chain.run(push, keep_record=True)
        off = np.abs(run.record.com[..., 1]).max(axis=1)  # (F,) largest |y| per frame [m]
        first = np.flatnonzero(off > 1e-6)
        when = f"{run.record.times[first[0]]:.3f} s" if first.size else "never"
        print(
            f"member {m}: v = {run.wave.speed:.4f} m/s; off the plane by > 1 um from {when};"
            f" largest |y| {off.max():.3g} m"
        )


if __name__ == "__main__":
    main()

"""Resolution study: clump dominoes of 5, 10, 20, 40 spheres per column against the box.

The chain of docs/fig6.md's base configuration (``ChainParams`` defaults) at each d/l, with
clump dominoes of ``spheres_per_column`` in {5, 10, 20, 40} (same mass, height and k_n:
docs/chain.md) and with box dominoes (``shape = "box"``); ensembles of seeded perturbed
pushes (seed 0, jitter 1e-3). ``tail_speed``: mean over the members of the speed over the
last ``TAIL`` pitches, defined whether or not the wave settled. Writes a CSV and prints it.

``--standard``: the common 48 x 24 x 7.5 mm domino (l, w, s; ``box_vs_clump.STANDARD``)
instead of the paper's 5 x 2.5 x 0.5 cm one, every other parameter as above.
``--resolutions``: the clump's spheres per column (comma list, empty for none).
``--roundings``: the box's edge rounding radii r [m] (comma list; ``default`` is the box
default s/20; ``r < s/2``).

Run: ``python docs/shape/resolution.py [--members 4] [--d-over-l 0.4] [--model 2d]
[--asymmetry 0.02] [--base two] [--no-box] [--standard] [--resolutions 5,10,20,40]
[--roundings default,0.0036] --out CSV`` (``--base two``: clumps on the two-sphere base,
not held).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from box_vs_clump import STANDARD
from tail_speed import mean_and_stderr, tail_speeds, write_rows

from dominowave.chain import ChainParams, DominoChain

RESOLUTIONS = (5, 10, 20, 40)


def _numbers(text: str, kind: type) -> list:
    """The comma-separated numbers of ``text`` as ``kind`` (``default`` -> None)."""
    return [None if x == "default" else kind(x) for x in text.split(",") if x.strip()]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--members", type=int, default=4)
    ap.add_argument("--d-over-l", default="0.4")
    ap.add_argument("--model", default="2d")
    ap.add_argument("--asymmetry", type=float, default=0.0)
    ap.add_argument("--base", default=None, help="clump base: one (default) or two")
    ap.add_argument("--no-box", action="store_true", help="clumps only")
    ap.add_argument("--standard", action="store_true", help="48 x 24 x 7.5 mm dominoes")
    ap.add_argument("--resolutions", default=",".join(map(str, RESOLUTIONS)))
    ap.add_argument("--roundings", default="default", help="box rounding radii r [m]")
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    size = STANDARD if args.standard else {}
    common = dict(model=args.model, lateral_asymmetry=args.asymmetry, **size)
    clump = dict(base=args.base, held=False) if args.base == "two" else {}
    shapes = [dict(spheres_per_column=n, **clump) for n in _numbers(args.resolutions, int)]
    if not args.no_box:
        shapes += [
            dict(shape="box", rounding=r, held=False) for r in _numbers(args.roundings, float)
        ]
    rows = []
    for d in (float(x) for x in args.d_over_l.split(",")):
        for shape in shapes:
            p = ChainParams(d_over_l=d, **common, **shape)
            start = time.perf_counter()
            ens = DominoChain(p, sleep=False).ensemble(members=args.members, seed=0)
            tail = tail_speeds(ens, p.pitch)
            tail_mean, tail_stderr = mean_and_stderr(tail)
            rows.append(
                {
                    "model": args.model,
                    "asymmetry": args.asymmetry,
                    "height": p.height,
                    "d_over_l": d,
                    "shape": p.shape,
                    "spheres_per_column": p.n_column if p.shape == "clump" else 0,
                    "rounding": p.rounding_radius if p.shape == "box" else p.radius,
                    "base": p.base_layout if p.shape == "clump" else "flat",
                    "held": p.held,
                    "members": args.members,
                    "reached_all": tail.size,
                    "n_settled": int(sum(r.wave.settled for r in ens.runs)),
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

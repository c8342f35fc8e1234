"""A/B CPU time of two versions of the rod model's kernel, in one process.

The rod-model counterpart of ``ab_chain.py``: imports the working tree's ``dominowave``
and a copy of the package at git revision ``--base`` (as ``dominowave_base``), runs
``bench_rods.py``'s chain (``--n`` dominoes, d/l = 0.4, k/k* = 1e4, until the wave has
passed) with each, alternating which goes first, and reports the medians of the CPU
(process) times and whether the two versions' results are identical.

Run:  python benchmarks/ab_rods.py --base 051a02b [--n 1000] [--repeat 5] [--normal head-on]
"""

from __future__ import annotations

import argparse
import importlib
import tempfile
import time
from pathlib import Path

import numpy as np
from ab_chain import import_base

PUSH = 7.3  # ~ the EJ limit Omega (eq 9) at d/l = 0.4 [rad/s], as bench_rods.py


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", required=True, help="git revision to compare the working tree with")
    ap.add_argument("--n", type=int, default=1000, help="dominoes")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--normal", default="geometric", choices=("geometric", "head-on"))
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        import_base(args.base, Path(tmp))
        versions = {}
        for name, package in (("base", "dominowave_base"), ("new", "dominowave")):
            paper_chain = importlib.import_module(f"{package}.chain.theory_vs_rods").paper_chain
            simulate = importlib.import_module(f"{package}.rods").simulate
            simulate(paper_chain(0.4, 1e4, 3, normal=args.normal), push=PUSH)  # compile
            versions[name] = (paper_chain(0.4, 1e4, args.n, normal=args.normal), simulate)
        times = {name: np.zeros(args.repeat) for name in versions}
        runs = {}
        for r in range(args.repeat):
            for name in list(versions) if r % 2 == 0 else list(reversed(versions)):
                chain, simulate = versions[name]
                start = time.process_time()
                runs[name] = simulate(chain, push=PUSH)
                times[name][r] = time.process_time() - start
    same = all(
        np.array_equal(getattr(runs["base"], k), getattr(runs["new"], k), equal_nan=True)
        for k in ("events", "samples", "theta", "omega")
    )
    base, new = times["base"], times["new"]
    print(
        f"rods N = {args.n}, {args.normal}, {args.repeat} runs each, CPU time: {args.base} "
        f"median {np.median(base):.3f} s, working tree {np.median(new):.3f} s; ratio of "
        f"the medians {np.median(base) / np.median(new):.3f}, median of the pair ratios "
        f"{np.median(base / new):.3f}; results identical: {same}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

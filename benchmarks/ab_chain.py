"""A/B speed of two versions of the engine on the domino chain, in one process.

On a shared VM whose speed drifts by ~25 % between blocks of runs, comparing two versions
in two benchmark runs measures the drift. This script imports the working tree's
``dominowave`` and a copy of the package at git revision ``--base`` (renamed
``dominowave_base``) into one process and alternates them, member by member, over an
ensemble of perturbed pushes: the ensemble averages out the different chaotic trajectories
of versions whose floating-point results differ, the alternation the drift.

Run:  python benchmarks/ab_chain.py --base 0984542 [--n 30] [--members 16] [--steps S] [--cpu]
      [--model 3d] [--shape box] [--energy]
      (engines only, as bench_chain.py, or with the energy ledger a chain run keeps,
      ``--energy``; S defaults to the paper case's steps, scaled per domino)
"""

from __future__ import annotations

import argparse
import importlib
import re
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def import_base(revision: str, into: Path):
    """Extract ``src/dominowave`` at ``revision`` as the package ``dominowave_base``."""
    archive = into / "src.tar"
    with open(archive, "wb") as out:
        subprocess.run(
            ["git", "-C", str(ROOT), "archive", revision, "src/dominowave"], stdout=out, check=True
        )
    with tarfile.open(archive) as tar:
        tar.extractall(into, filter="data")
    package = into / "src" / "dominowave"
    for path in package.rglob("*.py"):
        text = path.read_text()
        text = re.sub(r"\bdominowave\.", "dominowave_base.", text)
        text = re.sub(r"\b(from|import) dominowave\b", r"\1 dominowave_base", text)
        path.write_text(text)
    package.rename(into / "src" / "dominowave_base")
    sys.path.insert(0, str(into / "src"))
    return importlib.import_module("dominowave_base.chain.scenario"), importlib.import_module(
        "dominowave_base.chain.build"
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", required=True, help="git revision to compare the working tree with")
    ap.add_argument("--n", type=int, default=30, help="dominoes")
    ap.add_argument("--members", type=int, default=16)
    ap.add_argument("--model", default="2d", choices=("2d", "3d"), help="the chain's model")
    ap.add_argument(
        "--shape", default="clump", choices=("clump", "box"), help="the dominoes' shape"
    )
    ap.add_argument(
        "--cpu", action="store_true", help="time the process's CPU time (a shared machine)"
    )
    ap.add_argument("--steps", type=int, default=0)
    ap.add_argument(
        "--energy", action="store_true", help="keep the energy ledger (track_energy=True)"
    )
    args = ap.parse_args(argv)
    if not args.steps:  # bench_chain.py's cases: the paper chain's steps, scaled per domino
        from bench_chain import case, steps_to_last_collision

        args.steps = steps_to_last_collision(case(30)) * args.n // 30
    steps = args.steps
    with tempfile.TemporaryDirectory() as tmp:
        base_scenario, base_build = import_base(args.base, Path(tmp))
        from dominowave.chain import build, scenario

        versions = {}
        for name, (sc, bu) in {
            "base": (base_scenario, base_build),
            "new": (scenario, build),
        }.items():
            shape = {"base": "two"} if args.shape == "clump" else {"shape": "box"}
            params = bu.ChainParams(
                n_dominoes=args.n, d_over_l=0.4, held=False, model=args.model, **shape
            )
            versions[name] = sc.DominoChain(params)

        def run(name: str, member: int) -> float:
            chain = versions[name]
            factor = 1.0 + 1e-3 * np.random.default_rng([0, member]).standard_normal()
            sim, _ = chain.build(
                chain.resolve(None).scaled(factor), record=False, track_energy=args.energy
            )
            start = time.process_time() if args.cpu else time.perf_counter()
            sim.run(n_steps=steps)
            return (time.process_time() if args.cpu else time.perf_counter()) - start

        for name in versions:
            run(name, 0)  # compile / warm up
        times = {name: np.zeros(args.members) for name in versions}
        for member in range(args.members):
            order = list(versions) if member % 2 == 0 else list(reversed(versions))
            for name in order:  # (alternating which version runs first)
                times[name][member] = run(name, member)
    base, new = times["base"], times["new"]
    print(
        f"N = {args.n} ({args.shape}, {args.model}), {args.members} members x {steps} steps,"
        f" engines only{' with the energy ledger' if args.energy else ''}, "
        f"{'CPU' if args.cpu else 'wall'} time: {args.base} "
        f"{base.mean() / steps * 1e6:.2f} us/step, working tree "
        f"{new.mean() / steps * 1e6:.2f} us/step; speed-up of the means "
        f"{base.mean() / new.mean():.3f}, median of the member ratios "
        f"{np.median(base / new):.3f}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Floor friction phi_f in the 2D Fig 6 chain: large ensembles and the backward-toppling mode.

Reproduces the table of docs/fig6.md, section "Floor friction": for each (d/l, phi_f) an
ensemble of perturbed pushes of the 30-domino 2D base chain of Fig 6 (k/k* = 1e4, no
damping), built exactly as the Fig 6 sweep builds its members (seed 0, member m: push
factor 1 + 1e-3 N(0, 1) from numpy.random.default_rng([0, m])), so members 0-7 are those
of `dominowave paper-fig6`. Speeds are v / sqrt(g l).

Columns: members (settled); mean +- standard error, median and 20 % trimmed mean of the
settled speeds; "stalling": settled speed < 0.6; "backward fall": members in which some
domino n >= 1 moves by mechanism III (Fig 5A) after its first hit and leans back by
60-150 deg (it falls backwards onto n - 1); mean |base slip| [cm].

    python docs/fig6/phi_f_study.py                       # the table of docs/fig6.md
    python docs/fig6/phi_f_study.py --phi 0.2,0.4,0.5,1.0 --d-over-l 0.7,0.8 --members 64

Output of the first command: docs/fig6/phi_f_study.txt (its header names date, commit
and wall time).
"""

from __future__ import annotations

import argparse
import math
import multiprocessing as mp
import time

import numpy as np

BACKWARD_LEAN = (math.radians(60), math.radians(150))  # 150: not a domino wrapping past 180
STALLING = 0.6  # v / sqrt(g l)


def run_member(task: tuple[float, float, int, int]) -> dict:
    """One ensemble member (in a worker process): its speed and backward falls."""
    from dominowave.chain import ChainParams, DominoChain

    d_over_l, phi_f, member, n = task
    chain = DominoChain(ChainParams(n_dominoes=n, d_over_l=d_over_l, friction_floor=phi_f))
    factor = 1.0 + 1e-3 * np.random.default_rng([0, member]).standard_normal()
    run = chain.run(chain.resolve(None).scaled(factor))
    ev = run.events
    lean = ev.max_backward[1:]
    backward = (ev.mechanism[1:] == 3) & (lean > BACKWARD_LEAN[0]) & (lean < BACKWARD_LEAN[1])
    scale = math.sqrt(chain.params.g * chain.params.height)
    return {
        "key": (d_over_l, phi_f),
        "speed": run.wave.speed / scale,
        "backward": bool(backward.any()),
        "slip": float(np.mean(np.abs(ev.slip_final[:-1]))),
    }


def table(rows: list[dict]) -> str:
    """The markdown table of the members ``rows`` (of every (d/l, phi_f))."""
    from scipy.stats import trim_mean

    lines = [
        "| d/l | phi_f | members (settled) | mean +- s.e. | median | 20 % trimmed mean "
        "| stalling (< 0.6) | members with a backward fall | mean abs slip [cm] |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for key in sorted({r["key"] for r in rows}):
        group = [r for r in rows if r["key"] == key]
        speed = np.array([r["speed"] for r in group])
        s = speed[np.isfinite(speed)]
        back = sum(r["backward"] for r in group)
        slip = 100 * np.mean([r["slip"] for r in group])
        lines.append(
            f"| {key[0]:g} | {key[1]:g} | {len(group)} ({s.size}) | {s.mean():.3f} +- "
            f"{s.std(ddof=1) / math.sqrt(s.size):.3f} | {np.median(s):.3f} | "
            f"{trim_mean(s, 0.2):.3f} | {100 * np.mean(s < STALLING):.0f} % | "
            f"{100 * back / len(group):.0f} % | {slip:.1f} |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--d-over-l", default="0.3,0.6,0.7,0.8")
    parser.add_argument("--phi", default="0.3,0.6", help="floor friction values phi_f")
    parser.add_argument("--members", type=int, default=96)
    parser.add_argument("--n", type=int, default=30, help="dominoes per chain")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    tasks = [
        (float(d), float(phi), m, args.n)
        for d in args.d_over_l.split(",")
        for phi in args.phi.split(",")
        for m in range(args.members)
    ]
    from dominowave.cli import version_line

    start = time.perf_counter()
    with mp.get_context("spawn").Pool(args.workers) as pool:
        rows = pool.map(run_member, tasks, chunksize=4)
    print(
        f"{version_line()}, {time.strftime('%d %b %Y %H:%M UTC', time.gmtime())}, "
        f"{len(tasks)} runs of {args.n} dominoes in {time.perf_counter() - start:.0f} s "
        f"({args.workers} worker processes)\n"
    )
    print(table(rows))


if __name__ == "__main__":
    main()

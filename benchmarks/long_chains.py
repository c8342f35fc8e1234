"""Where the time of a standard box chain goes as it grows: build, engine, analysis.

The standard chain (standard dominoes of ``chain.presets.standard_domino``, 3D, gap
9.38 mm, felt floor, friction 0.3 between the dominoes and with the floor, domino 0
pushed with ``sqrt(g/l)``) at the package's defaults (fidelity 2 %, held until touched,
asleep at rest), at several lengths.  For each length, ``--repeat`` runs with warm
kernels (one warm-up first; the lengths interleaved, one run of each per round), and the
median CPU time of each part of the run:

* build: ``DominoChain(p)`` and its stepper (scene, time step estimate);
* engine: ``stepper.advance`` to the end of the run (the DEM steps, the frames and the
  contact events kept);
* analysis: ``stepper.result()`` (the events of every domino from the frames it moves
  in, the wave fit, the theory beside it);

with the steps, the engine's CPU time per step and per domino, the dominoes awake on
average over the run (sampled every 2000 steps), the share of the dense frames (frames x
dominoes) that the run stores (``chain.frames``) and the front speed fitted from domino 10
on, and the median (and range) over the rounds of the whole run's cost over that of the
shortest chain.  A cost per domino that does not grow with the chain is the aim; the dominoes awake
behind the front set the cost of a step (docs/shape.md, "Sleeping dominoes").

Run:  python benchmarks/long_chains.py [--n 30,100,300] [--repeat 3]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np

from dominowave.chain import DominoChain, Push
from dominowave.chain.presets import standard_domino
from dominowave.chain.wave import speed_from

FIT_FROM = 10
SAMPLE = 2000  # steps between counts of the dominoes awake


def one_run(n: int) -> dict[str, float]:
    """CPU times [s] of the parts of one run of the standard chain of ``n`` dominoes."""
    p = standard_domino(
        gap=0.00938, floor="felt", n_dominoes=n, friction_dominoes=0.3, friction_floor=0.3
    )
    t0 = time.process_time()
    stepper = DominoChain(p).stepper(Push(omega=math.sqrt(p.g / p.height)))
    t1 = time.process_time()
    awake, engine = [], 0.0
    while True:
        start = time.process_time()
        done = stepper.advance(SAMPLE)  # (in pieces: the same bits as in one)
        engine += time.process_time() - start
        awake.append(int(np.sum(stepper.sim.bodies.held == 0)))
        if done:
            break
    t2 = time.process_time()
    result = stepper.result()
    t3 = time.process_time()
    frames = stepper.frames
    stored = sum(track.frames.size for track in frames.tracks()) / (frames.n_frames * n)
    return {
        "build": t1 - t0,
        "engine": engine,
        "analysis": t3 - t2,
        "steps": stepper.steps,
        "awake": float(np.mean(awake)),
        "stored": stored,
        "speed": speed_from(result.arrival, result.positions, FIT_FROM).speed,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", default="30,100,300", help="chain lengths")
    parser.add_argument("--repeat", type=int, default=3, help="runs per length")
    args = parser.parse_args()
    one_run(12)  # warm the kernels: compiling is not the run's time
    lengths = [int(x) for x in args.n.split(",")]
    # the lengths interleaved, one run each per round, so that a drift of the machine
    # reaches every length alike, and each round gives one ratio of costs
    runs = {n: [] for n in lengths}
    for _ in range(args.repeat):
        for n in lengths:
            runs[n].append(one_run(n))
    print(
        f"| dominoes | build [s] | engine [s] | analysis [s] | total [s] | steps | us/step"
        f" | ns per domino-step | awake (mean) | frames stored [%] | speed [m/s]"
        f" | total over {lengths[0]} (range) |  (median CPU of {args.repeat} interleaved rounds)"
    )
    print("|---" * 12 + "|")
    for n in lengths:
        med = {k: statistics.median(r[k] for r in runs[n]) for k in runs[n][0]}
        total = med["build"] + med["engine"] + med["analysis"]
        per_step = med["engine"] / med["steps"]
        pairs = zip(runs[lengths[0]], runs[n], strict=True)
        ratios = [_total(long) / _total(short) for short, long in pairs]
        print(
            f"| {n} | {med['build']:.3f} | {med['engine']:.3f} | {med['analysis']:.3f}"
            f" | {total:.3f} | {med['steps']:.0f} | {per_step * 1e6:.1f}"
            f" | {per_step / n * 1e9:.0f} | {med['awake']:.1f} | {100 * med['stored']:.1f}"
            f" | {med['speed']:.4f} | {statistics.median(ratios):.2f}"
            f" ({min(ratios):.2f}-{max(ratios):.2f}) |",
            flush=True,
        )


def _total(run: dict[str, float]) -> float:
    """The CPU time [s] of a whole run: build, engine and analysis."""
    return run["build"] + run["engine"] + run["analysis"]


if __name__ == "__main__":
    main()

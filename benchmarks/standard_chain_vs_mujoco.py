"""Time to solution on real dominoes: the standard 40-domino chain, dominowave beside MuJoCo.

The chain: 40 standard dominoes (48 x 24 x 7.5 mm, 8 g), 3D, clear gap 9.38 mm, friction
0.3 between the dominoes and with the floor, domino 0 pushed with ``sqrt(g/l)``, the
front speed fitted from domino 10 on (pitch-based). Each configuration below is run in
turn, ``--repeat`` rounds of interleaved runs (one of each per round, so that a load on
the shared machine falls on all of them alike), and the median wall time of each is
reported with its speed:

* dominowave with the package's defaults (the softest contact within 2 % of the
  plastic's speed and its step, T_c/10 at that tolerance, ``chain.fidelity``; dominoes
  held until touched and put to sleep once at rest);
* the same until the wave touches the last domino (``tail_time=0``, no aftermath), where
  MuJoCo's loop stops too: the run that gives the speed and nothing else;
* dominowave at the plastic's own stiffness (``fidelity="exact"``);
* dominowave at other tolerances (``--tolerances``, default 1 % and 5 %, the latter the
  error of MuJoCo's default run), whole and to the last touch;
* dominowave with the stiffness set by ``stiffness_ratio`` (``--ratios``);
* with ``--breakdown``, the defaults' settings taken away one at a time, to show where
  their time comes from: every domino free (``held=False``) and awake (``sleep=False``)
  at the plastic's stiffness (T_c/50), then the softened contact at T_c/50, at its own
  step T_c/10, and held until touched (still awake);
* MuJoCo (``benchmarks/mujoco_chain.py``: exact boxes, elliptic cones, implicitfast), with
  its default contacts at dt 1e-3 s and with the 2 ms contacts of the cross-check at
  dt 2e-4 s.

Wall time of dominowave: the whole ``DominoChain(p).run(push)`` with warm kernels (one
warm-up run first); of MuJoCo: its stepping loop (model build and settling excluded).
The last column divides each run's wall time by that of MuJoCo's default run in the
same round, the median over the rounds: a ratio that a slow drift of a shared machine
moves less than the times themselves.

Usage::

    python benchmarks/standard_chain_vs_mujoco.py [--repeat 3] [--tolerances 0.01,0.05]
        [--ratios 1e4,1e5] [--breakdown]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

from mujoco_chain import run_chain  # the MuJoCo chain of this folder

from dominowave.chain import DominoChain, Push
from dominowave.chain.build import chain_positions
from dominowave.chain.presets import standard_domino
from dominowave.chain.wave import speed_from

GAP, FRICTION, N, FIT_FROM = 0.00938, 0.3, 40, 10
MUJOCO_DEFAULT = "MuJoCo, default contacts, dt 1e-3 s"


def dominowave_run(
    stiffness_ratio: float | None, fidelity=None, held=True, **options
) -> tuple[float, float]:
    """(front speed [m/s], wall time [s]) of the standard chain in dominowave;
    ``options`` go to ``DominoChain`` (``sleep``, ``steps_per_collision``, ``tail_time``)."""
    extra = {} if stiffness_ratio is None else {"stiffness_ratio": stiffness_ratio}
    p = standard_domino(
        gap=GAP, floor="felt", n_dominoes=N, friction_dominoes=FRICTION, friction_floor=FRICTION,
        held=held, **extra,
    )  # fmt: skip
    start = time.perf_counter()
    chain = DominoChain(p, fidelity=fidelity, **options)
    run = chain.run(Push(omega=math.sqrt(p.g / p.height)))
    wall = time.perf_counter() - start
    return speed_from(run.arrival, chain_positions(p), FIT_FROM).speed, wall


def mujoco_run(dt: float, solref_tc: float) -> tuple[float, float]:
    """(front speed [m/s], wall time of the stepping loop [s]) of the chain in MuJoCo."""
    run = run_chain(N, GAP, FRICTION, FRICTION, dt, fit_from=FIT_FROM, solref_tc=solref_tc)
    return run.speed, run.wall_s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="interleaved rounds")
    parser.add_argument("--ratios", default="1e4,1e5", help="stiffness ratios k/k* to add")
    parser.add_argument(
        "--tolerances",
        default="0.01,0.05",
        help="fidelity tolerances to add (a run each, whole and to the last touch)",
    )
    parser.add_argument(
        "--breakdown", action="store_true", help="add the defaults' settings one at a time"
    )
    args = parser.parse_args()
    configs = {
        "dominowave, defaults": lambda: dominowave_run(None),
        "dominowave, defaults, to the last touch": lambda: dominowave_run(None, tail_time=0.0),
        "dominowave, fidelity exact": lambda: dominowave_run(None, "exact"),
    }
    for tol in (float(t) for t in args.tolerances.split(",") if t):
        configs[f"dominowave, fidelity {100 * tol:g} %"] = lambda f=tol: dominowave_run(None, f)
        configs[f"dominowave, fidelity {100 * tol:g} %, to the last touch"] = lambda f=tol: (
            dominowave_run(None, f, tail_time=0.0)
        )
    if args.breakdown:
        awake = {"held": False, "sleep": False}
        configs.update({
            "dominowave, exact, free and awake": lambda: dominowave_run(None, "exact", **awake),
            "dominowave, softened at T_c/50, free and awake":
                lambda: dominowave_run(None, steps_per_collision=50, **awake),
            "dominowave, softened, free and awake": lambda: dominowave_run(None, **awake),
            "dominowave, softened, held, awake": lambda: dominowave_run(None, sleep=False),
        })  # fmt: skip
    for ratio in (float(r) for r in args.ratios.split(",") if r):
        configs[f"dominowave, k/k* = {ratio:g}"] = lambda r=ratio: dominowave_run(r)
    configs[MUJOCO_DEFAULT] = lambda: mujoco_run(1e-3, 0.02)
    configs["MuJoCo, 2 ms contacts, dt 2e-4 s"] = lambda: mujoco_run(2e-4, 0.002)
    dominowave_run(1e4)  # warm the kernels: compiling is not time to solution
    results = {name: [] for name in configs}
    for _ in range(args.repeat):
        for name, run in configs.items():
            results[name].append(run())
    # each run against MuJoCo's default run of its own round: a drift of the machine
    # between rounds slows both alike
    reference = [w for _, w in results[MUJOCO_DEFAULT]]
    print(f"| code | speed [m/s] | wall [s], median of {args.repeat} | over MuJoCo's, median |")
    print("| --- | --- | --- | --- |")
    for name, runs in results.items():
        speeds = {round(v, 4) for v, _ in runs}
        wall = statistics.median(w for _, w in runs)
        ratio = statistics.median(w / r for (_, w), r in zip(runs, reference, strict=True))
        print(f"| {name} | {', '.join(f'{v:.4f}' for v in sorted(speeds))} | {wall:.3g} |"
              f" {ratio:.2f} |")  # fmt: skip


if __name__ == "__main__":
    main()

"""Box chains whose resting dominoes sleep against the same chains with every domino awake.

A box domino that has come to rest is put to sleep (``DominoChain(sleep=True)``, the
default of box chains): once every point of it has moved slower than ``v_s`` for
``t_s``, with the moving dominoes it touches, it costs nothing until a moving body
touches or drives it (``dem.Scene.build``'s ``sleep_speed`` and ``sleep_time``).  The
criterion is not exact; this script measures what it changes, for several criteria
``(v_s / sqrt(g l), t_s / sqrt(l/g))`` (``DominoChain``'s ``sleep_speed`` and
``sleep_time``).  For each chain and criterion it gives: the front speed fitted from
domino 10 on and its change against the chain awake, the largest relative change of the
arrival times (first touch) of dominoes 1 .. N-1, the CPU time of the whole run (warm
kernels: build, engine, analysis) and the dominoes asleep at the end.

The chains: standard dominoes (``chain.presets.standard_domino``, 3D, fidelity 1 %:
:data:`FIDELITY`) on felt with friction 0.3 between the dominoes and with the floor at the 9.38 mm
gap, 30 to 300 dominoes; three more 100-domino chains of standard dominoes (friction 0.1
between them; on hardwood at gaps of 15 mm and of 6 mm, friction 0.5 between them); and
the 2D chain of the paper's box dominoes (d/l = 0.4, k/k* = 1e4, friction 0.3).

Run:  python docs/shape/sleep_vs_awake.py [--n 30,100,300] [--criteria 1e-3:1,1e-2:0.5]
      [--out sleep_vs_awake.csv]
"""

from __future__ import annotations

import argparse
import csv
import math
import time

import numpy as np

from dominowave.chain import ChainParams, DominoChain, Push
from dominowave.chain.fidelity import given_materials
from dominowave.chain.presets import standard_domino
from dominowave.chain.wave import speed_from

FIT_FROM = 10


FIDELITY = 0.01
"""The fidelity of the standard dominoes' chains (``chain.fidelity``), at which the
table of docs/shape.md was measured."""


def chains(sizes: list[int]) -> dict[str, ChainParams]:
    """The chains measured, by name."""
    out = {}
    for n in sizes:
        out[f"standard 3D, felt, mu 0.3, {n}"] = standard_domino(
            gap=0.00938, floor="felt", n_dominoes=n, friction_dominoes=0.3, friction_floor=0.3
        )
    out["standard 3D, felt, mu_d 0.1, 100"] = standard_domino(
        gap=0.00938, floor="felt", n_dominoes=100, friction_dominoes=0.1, friction_floor=0.3
    )
    out["standard 3D, hardwood, gap 15 mm, 100"] = standard_domino(
        gap=0.015, floor="hardwood", n_dominoes=100
    )
    out["standard 3D, hardwood, gap 6 mm, mu_d 0.5, 100"] = standard_domino(
        gap=0.006, floor="hardwood", n_dominoes=100, friction_dominoes=0.5
    )
    out["paper's box 2D, 30"] = ChainParams(shape="box", n_dominoes=30, friction_dominoes=0.3)
    return out


def run(p: ChainParams, criterion: tuple[float, float] | None):
    """(arrival times [s], front speed [m/s], CPU time [s], dominoes asleep at the end) of
    the chain awake (``criterion`` None) or asleep by ``(v_s, t_s)``."""
    sleep = {"sleep": False} if criterion is None else dict(
        zip(("sleep_speed", "sleep_time"), criterion, strict=True)
    )  # fmt: skip
    start = time.process_time()
    fidelity = FIDELITY if given_materials(p) else None
    chain = DominoChain(p, fidelity=fidelity, **sleep)
    stepper = chain.stepper(Push(omega=math.sqrt(p.g / p.height)))
    stepper.advance(np.iinfo(np.int64).max)
    result = stepper.result()
    cpu = time.process_time() - start
    bodies = stepper.sim.bodies
    asleep = int(np.sum((bodies.held == 1) & np.isfinite(bodies.calm_since)))
    speed = speed_from(result.arrival, result.positions, FIT_FROM).speed
    return np.asarray(result.arrival), speed, cpu, asleep


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", default="30,100,300", help="standard chains' lengths")
    parser.add_argument(
        "--criteria",
        default="1e-3:1,3e-3:0.5,1e-2:0.5,1e-2:0.25,2e-2:0.5",
        help="v_s:t_s of each criterion",
    )
    parser.add_argument("--out", default="sleep_vs_awake.csv", help="CSV to write")
    args = parser.parse_args()
    criteria = [tuple(float(x) for x in c.split(":")) for c in args.criteria.split(",")]
    for p in (standard_domino(gap=0.00938, floor="felt", n_dominoes=12), ChainParams(shape="box")):
        run(p, (1e-2, 0.5))  # warm the kernels of both kinds: compiling is not the run's
    fields = ["chain", "v_s_sqrt_gl", "t_s_sqrt_l_over_g", "speed_m_s", "speed_change"]
    fields += ["largest_arrival_change", "cpu_s", "asleep_at_end"]
    with open(args.out, "w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(fields)
        for name, p in chains([int(n) for n in args.n.split(",")]).items():
            awake, v_awake, cpu, _ = run(p, None)
            rows = [["awake", "", f"{v_awake:.5f}", "", "", f"{cpu:.3g}", 0]]
            for criterion in criteria:
                arrival, v, cpu, asleep = run(p, criterion)
                change = np.nanmax(np.abs(arrival[1:] - awake[1:]) / awake[1:])
                rows.append([f"{criterion[0]:g}", f"{criterion[1]:g}", f"{v:.5f}"])
                rows[-1] += [f"{v / v_awake - 1:+.2e}", f"{change:.2e}", f"{cpu:.3g}", asleep]
            for row in rows:
                out.writerow([name, *row])
                print(dict(zip(fields, [name, *row], strict=True)), flush=True)


if __name__ == "__main__":
    main()

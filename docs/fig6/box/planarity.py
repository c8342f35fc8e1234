"""Does the symmetric 3D chain of Fig 6 stay in its plane, and how fast do lateral
perturbations grow in it?  Box dominoes by default, ``--shape clump`` for the paper's.

Per run: the wave speed (and that of the same member in 2D, the chain the symmetric 3D
one would equal if it stayed in its plane), the first times at which some domino's
centre has moved more than 1e-12, 1e-9, 1e-6 and 1e-3 m across the chain's line (from
its placement), the growth rate ``ln(1e3) / (t_1e-6 - t_1e-9)`` [1/s] between the middle
two (NaN if both are crossed in the same frame or never), and the largest lateral
displacement over the run.
Without a seed the chain is symmetric to round-off; ``--yaw`` seeds each domino with a
random yaw of up to that amplitude [rad] (``lateral_asymmetry``, seed 0), ``--safety``
sets the time step as a fraction of the critical one (default: the chain's),
``--stiffness-ratio`` the contact stiffness k/k* (default: the preset's 1e4), and
``--friction-dominoes`` the friction between dominoes (default: the preset's 0).

Run: ``python docs/fig6/box/planarity.py [--d-over-l 0.4] [--members 0 1 2 3]
[--yaw 0 1e-14 1e-12 ...] [--safety 0.1] [--shape clump] [--stiffness-ratio 1e5]
[--friction-dominoes 0.3]``
"""

from __future__ import annotations

import argparse
import dataclasses
import math

import numpy as np

from dominowave.chain import DominoChain
from dominowave.chain.paper_fig6 import fig6_params
from dominowave.chain.scenario import member_push_factor

THRESHOLDS = (1e-12, 1e-9, 1e-6, 1e-3)  # lateral displacements [m]


def member_run(params, member: int, safety: float | None, keep_record: bool = False):
    """Run ensemble member ``member`` of the chain ``params`` (the Fig 6 preset's push)."""
    chain = DominoChain(params, safety=safety, sleep=False)  # (as measured: awake)
    push = chain.resolve(None).scaled(member_push_factor(0, member, 1e-3))
    return chain.run(push, keep_record=keep_record)


def lateral_departure(params, member: int, safety: float | None):
    """Run one member of the 3D chain ``params``; returns the wave, the first times [s]
    (NaN: never) at which a domino's centre is more than each of THRESHOLDS off its start
    across the line, and the largest such displacement [m]."""
    run = member_run(params, member, safety, keep_record=True)
    y = run.record.com[..., 1]  # (F, N) [m]
    off = np.abs(y - y[0]).max(axis=1)  # (F,) largest lateral displacement per frame
    times = []
    for threshold in THRESHOLDS:
        beyond = np.flatnonzero(off > threshold)
        times.append(run.record.times[beyond[0]] if beyond.size else math.nan)
    return run.wave, times, off.max()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--d-over-l", type=float, default=0.4)
    ap.add_argument("--members", type=int, nargs="+", default=[0, 1, 2, 3])
    ap.add_argument("--yaw", type=float, nargs="+", default=[0.0])
    ap.add_argument("--safety", type=float, default=None)
    ap.add_argument("--shape", choices=("box", "clump"), default="box")
    ap.add_argument("--stiffness-ratio", type=float, default=None, help="k/k* (preset: 1e4)")
    ap.add_argument("--friction-dominoes", type=float, default=None, help="(preset: 0)")
    args = ap.parse_args()
    base = fig6_params("3d", args.d_over_l, 30, args.shape)
    if args.stiffness_ratio is not None:
        base = dataclasses.replace(base, stiffness_ratio=args.stiffness_ratio)
    if args.friction_dominoes is not None:
        base = dataclasses.replace(base, friction_dominoes=args.friction_dominoes)
    planar = dataclasses.replace(base, model="2d")
    for yaw in args.yaw:
        for m in args.members:
            params = dataclasses.replace(base, lateral_asymmetry=yaw)
            wave, times, largest = lateral_departure(params, m, args.safety)
            v_2d = member_run(planar, m, args.safety).wave.speed
            span = times[2] - times[1]  # (0 or NaN: no rate from these frames)
            rate = math.log(1e3) / span if span > 0 else math.nan
            when = ", ".join("never" if math.isnan(t) else f"{t:.3f}" for t in times)
            print(
                f"yaw {yaw:.0e} member {m}: v = {wave.speed:.4f} m/s (reached {wave.reached};"
                f" 2D {v_2d:.4f} m/s);"
                f" off the line by 1e-12/1e-9/1e-6/1e-3 m at {when} s;"
                f" growth {rate:.0f} /s; largest {largest:.3g} m"
            )


if __name__ == "__main__":
    main()

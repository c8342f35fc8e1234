"""YADE and dominowave against the independent rigid-body ODE as dt -> 0.

A 4-domino 2D chain on a frictionless floor (two-sphere base, no holding), the scene of
``compare_yade.py``: the first three collision times of each code, at the chain's time
step divided by the given factors, against ``planar_chain_collisions`` of
``tests/reference/planar_chain.py`` (scipy DOP853 of planar rigid bodies with the same
linear springs). Both codes report onsets interpolated inside the step by the same rule.
With ``--friction-floor F > 0`` the ODE (frictionless) no longer applies: the row gives
YADE relative to dominowave instead (``yade_vs_ours``), for each of the shear kinematics
given (``--shear-kinematics contact_point yade``: dominowave's default, and YADE's own
ratcheting-free shear rate, which YADE 2023.02a uses by default).

Run:  python benchmarks/yade/converge_yade.py [--d-over-l 0.4 0.6] [--divide 1 4 10]
      [--friction-floor 0.3] [--shear-kinematics contact_point yade]
Needs YADE 2023.02a (``yade`` on the PATH).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np
from compare_yade import run_yade, scene_dict

from dominowave.chain.build import ChainParams
from dominowave.chain.scenario import DominoChain

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))
from reference.planar_chain import chain_collisions

T_END = 0.16  # [s] long enough for the third collision at d/l <= 0.6


def reference(chain: DominoChain) -> np.ndarray:
    """First-contact times of dominoes 1..3 from the rigid-body ODE [s]."""
    return chain_collisions(chain, chain.resolve(None), t_end=T_END, max_step=2e-5)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--d-over-l", type=float, nargs="+", default=[0.4, 0.6])
    ap.add_argument("--divide", type=int, nargs="+", default=[1, 4, 10])
    ap.add_argument("--friction-floor", type=float, default=0.0)
    ap.add_argument(
        "--shear-kinematics",
        nargs="+",
        choices=["contact_point", "yade"],
        default=["contact_point"],
        help="dominowave's shear kinematics (YADE always runs with its own)",
    )
    args = ap.parse_args(argv)
    for d in args.d_over_l:
        params = ChainParams(
            n_dominoes=4, d_over_l=d, base="two", held=False, friction_floor=args.friction_floor
        )
        base = DominoChain(params)
        ode = reference(base) if args.friction_floor == 0.0 else None
        for k in args.divide:
            chain = DominoChain(params, dt=base.dt / k)
            push = chain.resolve(None)
            yade = run_yade(scene_dict(chain, push, "record", math.ceil(T_END / chain.dt)))
            theirs = np.array(yade["onset"][1:4])
            for kinematics in args.shear_kinematics:
                ours_chain = DominoChain(params.with_(shear_kinematics=kinematics), dt=chain.dt)
                ours = ours_chain.run(push).arrival[1:4]
                row = {
                    "d_over_l": d,
                    "dt": chain.dt,
                    "shear_kinematics": kinematics,
                    "yade_vs_ours": (theirs / ours - 1.0).tolist(),
                }
                print(json.dumps(row | _versus_ode(ode, ours, theirs)), flush=True)
    return 0


def _versus_ode(ode, ours, theirs) -> dict:
    """Both codes' collision times relative to the ODE's (frictionless floor only)."""
    if ode is None:
        return {}
    return {
        "ode": ode.tolist(),
        "ours_rel": (ours / ode - 1.0).tolist(),
        "yade_rel": (theirs / ode - 1.0).tolist(),
    }


if __name__ == "__main__":
    raise SystemExit(main())

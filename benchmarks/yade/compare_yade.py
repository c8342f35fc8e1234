"""Cross-check dominowave's DEM chain against YADE 2023.02a.

For d/l in {0.2, 0.4, 0.6}, the identical 2D chain (N = 30, s/l = 0.1, k/k* = 1e4,
phi_f = 0.3, phi_d = 0, no damping, two-sphere base, no holding) is run in both codes:

(a) the first three collision times (not yet chaotic), relative difference; both codes'
    onsets interpolated inside the step the same way (``t_n - delta_n / |v_n|``: dominowave's
    event log, ``chain_yade.py``'s ``onset``); also YADE's step times against ours rounded
    up to its step grid;
(b) ensembles of ``--members`` perturbed pushes (same factors in both codes): mean
    steady speeds must agree within twice their combined standard error;
(c) wall time of one run, both with contact recording (YADE: a PyRunner every step).

dominowave runs with each of the ``--shear-kinematics`` given (its default
``contact_point``, and ``yade``: YADE's ratcheting-free shear rate, which YADE 2023.02a
uses by default), against the same YADE runs; one JSON line per spacing and kinematics.

``--chain soft-held`` runs instead a soft chain held until touched (l = 0.1 m, s/l = 0.1, density
2000 kg/m^3, k_n = E R with E = 1.308e6 Pa, k_t/k_n = 0.25, one-sphere base, dominoes held
until touched, floor friction 0.3, none between dominoes).

Usage: ``python benchmarks/yade/compare_yade.py [--members 8] [--d-over-l 0.2 0.4 0.6]
[--shear-kinematics contact_point yade] [--chain default|soft-held] [--seed 0]
[--out results.json]``.
Skips (exit 0 with a message) if ``yade`` is not installed.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from dominowave.chain.build import ChainParams, place_domino
from dominowave.chain.scenario import DominoChain, Push
from dominowave.chain.wave import ensemble_stats, steady_speed

HERE = Path(__file__).resolve().parent


CHAINS = {
    "default": {"base": "two", "held": False},
    "soft-held": {
        "height": 0.1,
        "thickness": 0.01,
        "density": 2000.0,
        "young": 1.308e6,
        "young_rule": "yade",
        "kt_ratio": 0.25,
        "base": "one",
        "held": True,
    },
}


def params(d_over_l: float, n: int = 30, chain: str = "default", **changes) -> ChainParams:
    return ChainParams(n_dominoes=n, d_over_l=d_over_l, **CHAINS[chain], **changes)


def scene_dict(chain: DominoChain, push: Push, mode: str, steps: int) -> dict:
    """Everything YADE needs, computed by dominowave (identical input for both codes)."""
    p = chain.params
    v0, w0, _ = chain._push_velocities(push)
    sink = chain._sink()
    bodies = []
    for n, x in enumerate(chain.positions):
        bodies.append(
            {
                "centres": place_domino(chain.shape, x, 0.0, sink).tolist(),
                "radii": chain.shape.radii.tolist(),
                "density": chain.shape.density.tolist(),
                "bottom": chain.shape.bottom.tolist(),
                "velocity": list(v0) if n == 0 else [0.0, 0.0, 0.0],
                "angular_velocity": list(w0) if n == 0 else [0.0, 0.0, 0.0],
            }
        )
    return {
        "mode": mode,
        "dt": chain.dt,
        "g": p.g,
        "damping": p.damping,
        "kn": p.contact_stiffness,
        "radius": p.radius,
        "kt_ratio": p.kt_ratio,
        "density": p.density,
        "friction_floor": p.friction_floor,
        "friction_dominoes": p.friction_dominoes,
        "blocked": "yXZ" if p.model == "2d" else "",
        "held": p.held,
        "bodies": bodies,
        "max_steps": steps,
        "n_steps": steps,
    }


# The collider settings that are fastest for this scene (benchmarks/README.md): YADE
# 2023.02a's defaults at N = 30, the chain_yade.py default at N = 300. Neither changes a
# trajectory (collider_scan.py: bitwise identical final positions).
COLLIDERS = {
    "defaults": {"targetInterv": 100, "verletDist": -0.5},
    "targetInterv 0": {"targetInterv": 0, "verletDist": -1},
}


def run_yade(scene: dict) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        src, out = Path(tmp) / "scene.json", Path(tmp) / "out.json"
        src.write_text(json.dumps(scene))
        env = dict(os.environ, CHAIN_SCENE=str(src), CHAIN_OUT=str(out), OMP_NUM_THREADS="1")
        subprocess.run(
            ["yade", "-n", "-j1", "-x", str(HERE / "chain_yade.py")],
            env=env,
            check=True,
            capture_output=True,
            timeout=3600,
        )
        return json.loads(out.read_text())


def compare(
    d_over_l: float,
    members: int,
    seed: int = 0,
    jitter: float = 1e-3,
    kinematics: tuple[str, ...] = ("contact_point",),
    chain_name: str = "default",
) -> list[dict]:
    """One result per shear kinematics of dominowave, against the same YADE runs."""
    chains = {
        k: DominoChain(params(d_over_l, chain=chain_name, shear_kinematics=k)) for k in kinematics
    }
    chain = chains[kinematics[0]]
    base = chain.resolve(None)
    max_steps = math.ceil(chain.max_time / chain.dt)
    ours = {k: [] for k in kinematics}
    walls_ours = {k: [] for k in kinematics}
    theirs, theirs_steps, walls_yade = [], [], []
    for i in range(members):
        factor = 1.0 + jitter * np.random.default_rng([seed, i]).standard_normal()
        push = base.scaled(factor)
        for k, ours_chain in chains.items():
            start = time.perf_counter()
            ours[k].append(ours_chain.run(push).arrival)
            walls_ours[k].append(time.perf_counter() - start)
        y = run_yade(scene_dict(chain, push, "record", max_steps))
        walls_yade.append(y["wall_time"])
        theirs.append(np.array(y["onset"], dtype=float))
        theirs_steps.append(np.array(y["arrival"], dtype=float))
        if i == 0:
            yade_steps = np.array(y["arrival"][1:4], dtype=float)
    return [
        _summary(chain, k, ours[k], theirs, theirs_steps, yade_steps, walls_ours[k], walls_yade)
        for k in kinematics
    ]


def _summary(chain, kinematics, ours, theirs, theirs_steps, yade_steps, walls_ours, walls_yade):
    """Collision times, ensemble speeds and wall times of one kinematics against YADE."""
    # both interpolated inside the step (same rule)
    first3 = np.abs(theirs[0][1:4] / ours[0][1:4] - 1.0)
    # YADE's step times (first step that sees the overlap) vs ours rounded up to that grid
    ours_on_grid = np.ceil(ours[0][1:4] / chain.dt - 1e-9) * chain.dt
    first3_grid = np.abs(yade_steps / ours_on_grid - 1.0)
    speeds_ours = [steady_speed(a, chain.positions).speed for a in ours]
    speeds_yade = [steady_speed(a, chain.positions).speed for a in theirs]
    v_ours = ensemble_stats(speeds_ours)
    v_yade = ensemble_stats(speeds_yade)
    v_steps = ensemble_stats([steady_speed(a, chain.positions).speed for a in theirs_steps])
    combined = math.hypot(v_ours.stderr, v_yade.stderr)
    return {
        "d_over_l": chain.params.d_over_l,
        "shear_kinematics": kinematics,
        "dt": chain.dt,
        "first_three_ours": ours[0][1:4].tolist(),
        "first_three_yade": theirs[0][1:4].tolist(),
        "first_three_rel_diff": first3.tolist(),
        "first_three_max_rel_diff": float(first3.max()),
        "first_three_yade_step_times": yade_steps.tolist(),
        "first_three_max_rel_diff_on_step_grid": float(first3_grid.max()),
        "speed_ours": [v_ours.mean, v_ours.stderr, v_ours.n],
        "speed_yade": [v_yade.mean, v_yade.stderr, v_yade.n],
        "speed_diff_over_combined_stderr": abs(v_ours.mean - v_yade.mean) / combined,
        "speed_yade_from_step_times": [v_steps.mean, v_steps.stderr, v_steps.n],
        "member_speeds_ours": speeds_ours,  # (nan: not settled)
        "member_speeds_yade": speeds_yade,
        "wall_ours_mean": float(np.mean(walls_ours)),
        "wall_yade_record_mean": float(np.mean(walls_yade)),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--members", type=int, default=8)
    ap.add_argument("--seed", type=int, default=0, help="seed of the push perturbations")
    ap.add_argument("--d-over-l", type=float, nargs="*", default=[0.2, 0.4, 0.6])
    ap.add_argument(
        "--shear-kinematics",
        nargs="+",
        choices=["contact_point", "yade"],
        default=["contact_point"],
        help="dominowave's shear kinematics (YADE always runs with its own)",
    )
    ap.add_argument("--chain", choices=sorted(CHAINS), default="default")
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    if shutil.which("yade") is None:
        print("yade not installed: skipping the YADE cross-check")
        return 0
    results = []
    for d in args.d_over_l:
        runs = compare(
            d,
            args.members,
            args.seed,
            kinematics=tuple(args.shear_kinematics),
            chain_name=args.chain,
        )
        for r in runs:
            results.append(r)
            print(json.dumps(r))
            sys.stdout.flush()
    if args.out is not None:
        args.out.write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

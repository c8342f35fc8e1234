"""Which dominoes of a long box chain are awake, and how fast they move.

A box chain puts a domino to sleep once every point of it has moved slower than the
sleep speed ``v_s`` for ``t_s``, and the moving dominoes it touches too
(``DominoChain(sleep=True)``, the default of box chains; docs/shape.md, "Sleeping
dominoes").  What a step of a long chain costs is the dominoes awake behind the front.
This script runs the standard chain (standard dominoes of ``chain.presets.standard_domino``,
3D, felt, gap 9.38 mm, friction 0.3 between the dominoes and with the floor, domino 0
pushed with ``sqrt(g/l)``, the package's defaults) and, every ``--every`` steps, writes
for each awake domino how far it stands behind the front (the last domino touched) and
its speed bound over ``v_s``: ``(|v| + |omega| (R_core + 2 r)) / v_s``, the engine's own
test (``dem.engine._box_speed``: ``R_core`` the half-diagonal of the core box, ``r`` the
rounding), at the full-step velocities of the last kick.  A domino at 1 or more cannot
sleep; one below waits out ``t_s``, or touches a domino that still moves at ``v_s``.

Run:  python docs/shape/awake_profile.py [--n 300] [--every 10000] [--out awake_profile.csv]
"""

from __future__ import annotations

import argparse
import csv
import math

import numpy as np

from dominowave.chain import DominoChain, Push
from dominowave.chain.presets import standard_domino


def profile(n: int, every: int) -> tuple[list[dict], float]:
    """The rows (step, time [s], dominoes behind the front, speed bound / v_s) of every
    awake domino at every ``every``-th step, and ``v_s`` [m/s]."""
    p = standard_domino(
        gap=0.00938, floor="felt", n_dominoes=n, friction_dominoes=0.3, friction_floor=0.3
    )
    stepper = DominoChain(p).stepper(Push(omega=math.sqrt(p.g / p.height)))
    sim = stepper.sim
    boxes, v_sleep = sim.boxes, sim.settings.sleep_speed
    body = boxes.body  # (box x of the chain is domino x)
    bound = np.sqrt((boxes.half**2).sum(axis=1)) + 2.0 * boxes.radius  # [m]
    rows = []
    while True:
        done = stepper.advance(every)
        bodies = sim.bodies
        touched = np.flatnonzero(~np.isnan(bodies.release_time[body]))
        front = int(touched.max()) if touched.size else 0
        speed = np.linalg.norm(bodies.vel_full[body], axis=1)
        speed += np.linalg.norm(bodies.omega_full[body], axis=1) * bound
        for x in np.flatnonzero(bodies.held[body] == 0):
            rows.append(
                {
                    "step": stepper.steps,
                    "time_s": float(sim.time),
                    "behind_front": front - int(x),
                    "speed_over_v_sleep": float(speed[x] / v_sleep),
                }
            )
        if done:
            return rows, float(v_sleep)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=300, help="dominoes")
    parser.add_argument("--every", type=int, default=10000, help="steps between samples")
    parser.add_argument("--out", default="awake_profile.csv", help="CSV of the samples")
    args = parser.parse_args()
    rows, v_sleep = profile(args.n, args.every)
    with open(args.out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    steps = sorted({row["step"] for row in rows})
    awake = [sum(row["step"] == s for row in rows) for s in steps]
    fast = [sum(row["step"] == s and row["speed_over_v_sleep"] >= 1 for row in rows) for s in steps]
    print(f"v_s = {v_sleep:.4g} m/s; {len(steps)} samples")
    print(f"awake: {min(awake)} to {max(awake)} (mean {np.mean(awake):.1f})")
    print(f"at v_s or faster: {min(fast)} to {max(fast)} (mean {np.mean(fast):.1f})")
    slow = [a - f for a, f in zip(awake, fast, strict=True)]
    print(f"slower than v_s, awake: {min(slow)} to {max(slow)} (mean {np.mean(slow):.1f})")
    # the decay of the speed behind the front: median ratio of neighbours' speeds
    by_step: dict[int, dict[int, float]] = {}
    for row in rows:
        by_step.setdefault(row["step"], {})[row["behind_front"]] = row["speed_over_v_sleep"]
    ratios = [
        speeds[k] / speeds[k + 1]
        for speeds in by_step.values()
        for k in speeds
        if k >= 3 and k + 1 in speeds and speeds[k + 1] > 0
    ]
    print(f"speed of a domino over that of the next one behind it (3 or more behind the"
          f" front): median {np.median(ratios):.2f}")  # fmt: skip


if __name__ == "__main__":
    main()

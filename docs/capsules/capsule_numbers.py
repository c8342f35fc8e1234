"""The measured numbers of docs/dem.md "Capsules" (provenance D22), from the scenes of
tests/dem/test_dem_capsule.py: rolling on an incline, elastic collisions, the planar
against the general kernels, a capsule standing on a box.

Run:  python docs/capsules/capsule_numbers.py   (from the repository's root)
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "dem"))
import test_dem_capsule as scenes
from dem_scenes import momenta

G = scenes.G


def rolling(tilt_deg):
    acceleration, expected, spin, slip = scenes.rolling_down_an_incline(tilt_deg)
    print(
        f"rolling at {tilt_deg:g} deg: acceleration {acceleration / expected - 1:+.2e}"
        f" relative, omega r / v - 1 = {spin:+.2e}, slip work {slip:.1e} of the kinetic"
        " energy"
    )


def collision(partner, mu):
    sim = scenes._two_bodies(partner, mu)
    e0 = sim.energy()["total"]
    p0, L0 = momenta(sim)
    sim.run(until=0.4)
    p1, L1 = momenta(sim)
    print(
        f"collision with a {partner}, mu = {mu}: energy {(sim.energy()['total'] - e0) / e0:+.1e}"
        f" relative, momenta {np.abs(p1 - p0).max():.1e} kg m/s, {np.abs(L1 - L0).max():.1e}"
        " kg m^2/s"
    )


def planar_against_general(label, build):
    out = []
    for kernels in (True, False):
        sim, body = build()
        sim.planar_kernels = kernels
        res = sim.run(until=0.6 if label == "falling" else 0.3, trajectory_every=1000)
        rows = sim.boxes.rows
        n = rows.n[0]
        box_pair = (rows.j[:n] >= 0) & (rows.j[:n] < 2)  # (the capsule with the box)
        fn = rows.fn[:n] if label == "falling" else rows.fn[:n][box_pair]
        weight = sim.bodies.mass[body] * G / (2 if label == "falling" else 1)
        out.append(res.positions[:, body].copy())
        print(f"  {label}, {'planar' if kernels else 'general'}: rows {fn / weight - 1}")
    print(f"{label}: planar - general, max {np.abs(out[0] - out[1]).max():.1e} m")


if __name__ == "__main__":
    for tilt in (10.0, 20.0):
        rolling(tilt)
    for partner in ("capsule", "box"):
        for mu in (0.0, 0.4):
            collision(partner, mu)
    planar_against_general("falling", lambda: (scenes._falling_capsule().build(safety=0.05), 0))
    for first in (True, False):
        for x in (0.0, 1.234e-3):

            def standing(first=first, x=x):
                scene, body = scenes._standing_on_a_box(first, x)
                return scene.build(safety=0.05), body

            planar_against_general(f"standing, capsule first {first}, x = {x:g} m", standing)

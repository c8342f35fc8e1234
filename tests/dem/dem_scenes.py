"""Geometry helpers and scenes shared by the DEM tests."""

import numpy as np
from scipy.optimize import lsq_linear

from dominowave.dem import Material, Scene
from dominowave.dem.shapes.cuboid import MAX_POINTS

R = 0.005  # sphere radius of the test scenes [m]
RHO = 1000.0


def sphere_mass(radius=R, density=RHO):
    return density * 4.0 / 3.0 * np.pi * radius**3


def column(n, base=(0.0, 0.0, R), tilt=0.0, radius=R):
    """Centres of n touching spheres in a straight column tilted by `tilt` about +y."""
    axis = np.array([np.sin(tilt), 0.0, np.cos(tilt)])
    return np.asarray(base) + 2.0 * radius * np.arange(n)[:, None] * axis


def tilt_of(sim, quaternions, body=0):
    """Tilt angle about +y of the line from the first to the last sphere of `body`."""
    members = np.flatnonzero(sim.sphere_body == body)
    u = sim.spheres.local[members[-1]] - sim.spheres.local[members[0]]
    q = np.atleast_2d(quaternions)
    w, x, y, z = q.T
    # world x and z components of R(q) u
    ux = (1 - 2 * (y * y + z * z)) * u[0] + 2 * (x * y - w * z) * u[1] + 2 * (x * z + w * y) * u[2]
    uz = 2 * (x * z - w * y) * u[0] + 2 * (y * z + w * x) * u[1] + (1 - 2 * (x * x + y * y)) * u[2]
    return np.arctan2(ux, uz)


def spheres_in_a_box():
    """27 spheres (radius 4.5-5.5 mm, two materials) on a 3 x 3 x 3 grid 12 mm apart, each
    with its own velocity and spin, dropped into a box of five walls 40 mm wide."""
    scene = Scene(gravity=(0.0, 0.0, -9.81))
    soft = scene.add_material(Material(density=2500.0, kn=2e4, friction=0.5, restitution=0.3))
    hard = scene.add_material(Material(density=1200.0, kn=5e4, friction=0.2, restitution=0.8))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), soft)
    for axis in range(2):
        for side in (-1.0, 1.0):
            point, normal = np.zeros(3), np.zeros(3)
            point[axis], normal[axis] = 0.02 * side, -side
            scene.add_wall(point, normal, hard)
    rng = np.random.default_rng(7)
    for k in range(27):
        cell = np.array([k % 3, (k // 3) % 3, k // 9]) - 1.0
        centre = 0.012 * cell + np.array([0.0, 0.0, 0.03]) + rng.uniform(-1e-3, 1e-3, 3)
        scene.add_sphere(
            centre, rng.uniform(0.0045, 0.0055), (soft, hard)[k % 2],
            velocity=rng.uniform(-0.2, 0.2, 3), angular_velocity=rng.uniform(-30, 30, 3),
        )  # fmt: skip
    return scene.build(safety=0.3, track_energy=True, record_pairs=True)


def manifold_buffers():
    """The output arrays of a contact manifold (dem.shapes): normal, point, overlap, key."""
    return (
        np.zeros((MAX_POINTS, 3)),
        np.zeros((MAX_POINTS, 3)),
        np.zeros(MAX_POINTS),
        np.zeros(MAX_POINTS, np.int64),
    )


def core_distance(xi, Ri, hi, xj, Rj, hj):
    """Distance [m] of two cores (boxes; a capsule's segment) ``x + R u``, ``|u_m| <= h_m``:
    a bounded linear least-squares problem over the axes of nonzero extent, solved exactly
    (BVLS)."""
    hi, hj = np.asarray(hi, float), np.asarray(hj, float)
    A = np.hstack([Ri[:, hi > 0], -Rj[:, hj > 0]])
    lim = np.concatenate([hi[hi > 0], hj[hj > 0]])
    res = lsq_linear(A, xj - xi, bounds=(-lim, lim), method="bvls", tol=1e-14)
    return np.linalg.norm(A @ res.x - (xj - xi))


def at_core_gap(xi, Ri, hi, Rj, hj, u, gap, far=0.2, steps=45):
    """The centre of core j on the ray ``xi + s u`` (``u`` a unit vector, s in [0, far] m)
    where it is ``gap`` [m] from core i (bisection on :func:`core_distance`)."""
    lo = 0.0
    for _ in range(steps):
        mid = 0.5 * (lo + far)
        if core_distance(xi, Ri, hi, xi + mid * u, Rj, hj) < gap:
            lo = mid
        else:
            far = mid
    return xi + far * u


def momenta(sim):
    """Total linear [kg m/s] and angular momentum about the origin [kg m^2/s] of the
    bodies of ``sim`` at the full step, each (3,)."""
    b = sim.bodies
    p = (b.mass[:, None] * b.vel_full).sum(axis=0)
    L = (np.cross(b.pos, b.mass[:, None] * b.vel_full) + b.angmom_full).sum(axis=0)
    return p, L

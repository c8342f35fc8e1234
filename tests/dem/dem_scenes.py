"""Geometry helpers shared by the DEM tests."""

import numpy as np

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

"""The sphere's contact geometry: pure per-pair functions (numba), as the other shapes'.

Each shape pair has one pure function (jax-md style): positions and sizes in, the contact
normal and overlap out (:func:`sphere_sphere`, :func:`sphere_wall`), and the contact
point of a sphere (:func:`contact_point`); the sphere driver (contact.compute_forces)
maps them over the Verlet list.  Vectors pass as scalar triples: kept in registers,
whereas through a scratch array every component is a store and a reload (the compiler
cannot rule out that the scratch array aliases the state arrays it reads).
:func:`start_gaps` gives, in NumPy, the gaps of a scene's spheres as it is built (for
its checks).
"""

from __future__ import annotations

import math

import numpy as np

from dominowave.dem.compiled import inline_kernel

__all__ = ["contact_point", "sphere_sphere", "sphere_wall", "start_gaps"]


@inline_kernel(python_entry=True)
def sphere_sphere(xi0, xi1, xi2, xj0, xj1, xj2, rsum, keep):
    """Contact geometry of two spheres with centres ``x_i``, ``x_j`` [m] and radii
    summing to ``rsum`` = ``R_i + R_j`` [m].

    ``n = (x_j - x_i) / |x_j - x_i|`` is the unit normal from i to j, ``delta = R_i +
    R_j - |x_j - x_i|`` [m] the overlap (> 0 in contact; Cundall & Strack 1979, YADE's
    Ig2_Sphere_Sphere_ScGeom).  Returns ``(near, n0, n1, n2, delta)``.  Spheres that are
    apart, ``|x_j - x_i|^2 >= rsum^2`` (tested without a root: most listed pairs are),
    are resolved only if ``keep`` (a contact that is on needs the normal and the gap at
    which it ends); otherwise ``near`` is False and the rest is zero.
    """
    dx = xj0 - xi0
    dy = xj1 - xi1
    dz = xj2 - xi2
    d2 = dx * dx + dy * dy + dz * dz
    if d2 >= rsum * rsum and not keep:
        return False, 0.0, 0.0, 0.0, 0.0
    dist = math.sqrt(d2)
    inv_dist = 1.0 / dist  # (one division per normal)
    return True, dx * inv_dist, dy * inv_dist, dz * inv_dist, rsum - dist


@inline_kernel(python_entry=True)
def sphere_wall(xi0, xi1, xi2, radius, w0, w1, w2, nw0, nw1, nw2, keep):
    """Contact geometry of a sphere (centre ``x_i`` [m], ``radius`` [m]) and a wall (the
    plane through ``w`` [m] with unit normal ``nw`` pointing to the side of the spheres).

    The sphere's centre lies ``dist = (x_i - w) . nw`` [m] from the plane; the normal
    from the sphere to the wall is ``n = -nw`` and the overlap ``delta = radius - dist``
    [m] (YADE's Ig2_Wall_Sphere_ScGeom).  Returns ``(near, n0, n1, n2, delta)``, as
    :func:`sphere_sphere`: ``near`` is ``delta > 0 or keep``.
    """
    dist = (xi0 - w0) * nw0
    dist += (xi1 - w1) * nw1
    dist += (xi2 - w2) * nw2
    delta = radius - dist
    return delta > 0.0 or keep, -nw0, -nw1, -nw2, delta


@inline_kernel(python_entry=True)
def contact_point(xi0, xi1, xi2, radius, n0, n1, n2, overlap):
    """Contact point [m] midway through the overlap (YADE's ScGeom): ``p = x_i + (R_i -
    delta / 2) n`` for sphere i (centre ``x_i``, ``radius`` R_i), normal ``n`` from i to
    its partner and overlap ``delta`` [m]."""
    reach = radius - 0.5 * overlap
    return xi0 + reach * n0, xi1 + reach * n1, xi2 + reach * n2


def start_gaps(spheres, walls):
    """The spheres' distances [m] as a scene is built (NumPy, for the checks of the set-up).

    Returns ``(height, i, j, gap)``: ``height`` (nw, ns) the height of each sphere's centre
    over each wall, along its normal (an overlap where it is below the radius); ``i, j``
    (np,) the pairs of spheres of different bodies whose centres are within twice the
    largest radius (scipy's cKDTree), and ``gap`` (np,) their surface distance (negative:
    an overlap)."""
    from scipy.spatial import cKDTree

    pos, radius, body = spheres.pos, spheres.radius, spheres.body
    height = np.array([(pos - p) @ n for p, n in zip(walls.point, walls.normal, strict=True)])
    height = height.reshape(walls.point.shape[0], pos.shape[0])
    pairs = cKDTree(pos).query_pairs(2.0 * float(radius.max()), output_type="ndarray")
    i, j = pairs.reshape(-1, 2).T
    other = body[i] != body[j]
    i, j = i[other], j[other]
    gap = np.linalg.norm(pos[i] - pos[j], axis=1) - (radius[i] + radius[j])
    return height, i, j, gap

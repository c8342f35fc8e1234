"""Distances between cuboid cores, walls and points: the overlap of rounded cuboids.

A rounded cuboid is its core box swept by a ball of radius r, so two rounded bodies
overlap by delta = r_a + r_b - D, D the distance between their cores; a rounded box and
a wall by r - D; a rounded box and a sphere of radius R by r + R - D (D to the sphere's
centre). The contact normal is the unit vector between the cores' closest points, and
D, hence the contact force, is a continuous function of the two poses whatever feature
pair (vertex-face, edge-edge, face-face) realises it.

A box has centre c (3,) [m], rotation R (3, 3) (columns: its axes in the world frame)
and half-extents h (3,) [m]: its points are c + R u with |u_k| <= h_k. The distance of
two boxes is a bounded linear least-squares problem,

    D = min || (c_a + R_a u) - (c_b + R_b w) ||  over |u_k| <= h_a,k, |w_k| <= h_b,k,

solved exactly (to round-off) by scipy's lsq_linear with the bounded-variable
least-squares active-set method (Stark & Parker 1995). A box and a point: clamp the
point's body coordinates to the box. A box and a wall (point p0, unit normal n): the
lowest corner, D = n . (c - p0) - sum_k h_k |n . R e_k|. Planar boxes (2D) are these
with the y extent unused. No import of dominowave. Units: SI.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import lsq_linear


def box_box_distance(centre_a, rotation_a, half_a, centre_b, rotation_b, half_b):
    """(D [m], closest point on box a (3,), closest point on box b (3,)) of two boxes
    (module docstring). D = 0 when the boxes intersect (then the points are some common
    point). For parallel faces the closest points are not unique; D is."""
    centre_a, centre_b = np.asarray(centre_a, float), np.asarray(centre_b, float)
    rotation_a, rotation_b = np.asarray(rotation_a, float), np.asarray(rotation_b, float)
    half = np.concatenate((np.asarray(half_a, float), np.asarray(half_b, float)))
    matrix = np.hstack((rotation_a, -rotation_b))
    free = half > 0.0  # a zero extent (a point, a segment, a rectangle) is no unknown
    bounds = (-half[free], half[free])
    x = np.zeros(6)
    x[free] = lsq_linear(
        matrix[:, free], centre_b - centre_a, bounds=bounds, method="bvls", tol=1e-15
    ).x
    point_a = centre_a + rotation_a @ x[:3]
    point_b = centre_b + rotation_b @ x[3:]
    return float(np.linalg.norm(point_b - point_a)), point_a, point_b


def box_point_distance(centre, rotation, half, point):
    """(D [m], closest point of the box (3,)) to ``point`` (3,): clamp in the body frame;
    D = 0 inside."""
    rotation = np.asarray(rotation, float)
    local = rotation.T @ (np.asarray(point, float) - np.asarray(centre, float))
    closest = np.asarray(centre, float) + rotation @ np.clip(local, -half, half)
    return float(np.linalg.norm(np.asarray(point, float) - closest)), closest


def box_wall_distance(centre, rotation, half, wall_point, wall_normal):
    """Signed distance [m] from the wall (the plane through ``wall_point`` with unit
    normal ``wall_normal``, pointing to the free side) to the box's lowest corner:
    n . (c - p0) - sum_k h_k |n . R e_k| (negative: the core crosses the wall)."""
    n = np.asarray(wall_normal, float)
    reach = np.abs(n @ np.asarray(rotation, float)) @ np.asarray(half, float)
    return float(n @ (np.asarray(centre, float) - np.asarray(wall_point, float)) - reach)

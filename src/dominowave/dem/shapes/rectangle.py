"""The rounded cuboid in a planar scene: a rounded rectangle moving in the xz plane.

The body is the cuboid of :mod:`dominowave.dem.shapes.cuboid` (core half-extents ``h``,
rounding ``r``) turning about the world y axis only; its box axes 0 and 2 lie in the xz
plane.  Its contacts are those of the cuboid with every point taken at the body's own y:
the 3D manifold of such a scene consists of pairs of points at the two ends (``y = +-b``)
of each edge parallel to y, with equal overlaps and normals, and this module returns one
point per pair -- the caller counts each :func:`multiplicity` times (twice,
``PLANAR_MULTIPLICITY``, or once where a core has no extent along y: a capsule's).  The geometry is
the 2D version of the same method: separating axes over the 2 + 2 face normals, the
incident edge clipped against the reference edge's two side lines (a face on a face: 2
points), and the exact deepest point -- a corner-edge pair in 2D -- merged in as in 3D
(and, as there, not searched for where the separating axes prove a corner exact).
Arguments and output as in ``cuboid`` (y components of the normals 0).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from dominowave.dem.compiled import inline_kernel, inner_kernel
from dominowave.dem.shapes.cuboid import (
    distinct_vertex,
    manifold_is_deepest,
    merge_deepest,
    owner_first,
    plane_row,
    point_box_distance,
    rows_from,
    sphere_point,
    unit_sign,
    vertex_owner,
)

__all__ = [
    "PLANAR_MULTIPLICITY",
    "distinct_corner",
    "edges_separate",
    "multiplicity",
    "rect_plane",
    "rect_rect",
    "rect_sphere",
]

PLANAR_MULTIPLICITY = 2  # the two ends y = +-b of a cuboid edge parallel to y
KEY_VERTEX = 2 * 4 * 4 * 4


@inline_kernel()
def _corner(x, R, h, k):
    """World (x, z) of corner k of the rectangle (bit 0: + axis 0, bit 1: + axis 2)."""
    s0 = h[0] if k & 1 else -h[0]
    s2 = h[2] if k & 2 else -h[2]
    return x[0] + s0 * R[0, 0] + s2 * R[0, 2], x[2] + s0 * R[2, 0] + s2 * R[2, 2]


@inline_kernel()
def distinct_corner(h, k):
    """False if corner k coincides with a corner of lower id: cuboid.distinct_vertex of
    the vertex whose bits 0 and 2 are those of the corner (a capsule's segment)."""
    return distinct_vertex(h, (k & 1) | ((k & 2) << 1))


@inline_kernel()
def multiplicity(hi, hj):
    """The number of contact points a planar row stands for: the two ends ``y = +-b`` of
    a cuboid edge along y (:data:`PLANAR_MULTIPLICITY`), or one where a body's core has
    no extent along y (a capsule lying in the plane touches at one point).  ``hj`` is
    ``hi`` for a wall."""
    if hi[1] == 0.0 or hj[1] == 0.0:
        return 1.0
    return float(PLANAR_MULTIPLICITY)


@njit(cache=True, error_model="numpy", _nrt=False)
def rect_plane(x, R, h, r, p0, nw, margin, normal, point, overlap, key):
    """Contacts of a rounded rectangle with the plane through ``p0``, unit normal ``nw``
    (in the xz plane): one point per corner within ``r + margin`` (a face on the plane: 2),
    overlap ``r - d``, normal ``-nw``; key = corner id."""
    n = 0
    for k in range(4):
        if not distinct_corner(h, k):
            continue
        v0, v2 = _corner(x, R, h, k)
        d = (v0 - p0[0]) * nw[0] + (x[1] - p0[1]) * nw[1] + (v2 - p0[2]) * nw[2]
        if d < r + margin:  # (no y in the normal: the point's y is the body's own, x[1] + 0)
            plane_row(v0, x[1], v2, d, r, -nw[0], 0.0, -nw[2], k, n, normal, point, overlap, key)
            n += 1
    return n


@inline_kernel()
def _separation(d0, d2, L0, L2, Ri, hi, Rj, hj):
    """Gap [m] of the two core rectangles along the in-plane unit axis L."""
    radius = 0.0
    for m in (0, 2):
        radius += hi[m] * abs(L0 * Ri[0, m] + L2 * Ri[2, m])
        radius += hj[m] * abs(L0 * Rj[0, m] + L2 * Rj[2, m])
    return abs(L0 * d0 + L2 * d2) - radius


@inline_kernel()
def edges_separate(xi, Ri, hi, xj, Rj, hj, reach):
    """True if an edge normal of rectangle i or j separates the two cores by at least
    ``reach`` [m]: the early exit of :func:`rect_rect`, in the same order and arithmetic
    (a caller may skip the call without changing any result)."""
    d0, d2 = xj[0] - xi[0], xj[2] - xi[2]
    for m in (0, 2):
        if _separation(d0, d2, Ri[0, m], Ri[2, m], Ri, hi, Rj, hj) >= reach:
            return True
        if _separation(d0, d2, Rj[0, m], Rj[2, m], Ri, hi, Rj, hj) >= reach:
            return True
    return False


@inner_kernel(_nrt=False)
def _edge_manifold(xA, RA, hA, rA, kA, xB, RB, hB, rB, margin, sign, swap, out):
    """Clip the incident edge of B against the reference edge (face axis ``kA``) of A."""
    normal, point, overlap, key = out
    d0, d2 = xB[0] - xA[0], xB[2] - xA[2]
    sA = unit_sign(d0 * RA[0, kA] + d2 * RA[2, kA])
    n0, n2 = sA * RA[0, kA], sA * RA[2, kA]
    ku = 2 - kA
    t0, t2 = RA[0, ku], RA[2, ku]
    c0, c2 = xA[0] + hA[kA] * n0, xA[2] + hA[kA] * n2
    kB = 0 if abs(n0 * RB[0, 0] + n2 * RB[2, 0]) >= abs(n0 * RB[0, 2] + n2 * RB[2, 2]) else 2
    sB = -unit_sign(n0 * RB[0, kB] + n2 * RB[2, kB])
    mB = 2 - kB
    f0, f2 = xB[0] + sB * hB[kB] * RB[0, kB], xB[2] + sB * hB[kB] * RB[2, kB]
    # the incident edge's two corners in reference coordinates (u along the edge, n up)
    e0 = f0 + hB[mB] * RB[0, mB] - c0
    e2 = f2 + hB[mB] * RB[2, mB] - c2
    u_a, n_a, sub_a = e0 * t0 + e2 * t2, e0 * n0 + e2 * n2, 0
    e0 = f0 - hB[mB] * RB[0, mB] - c0
    e2 = f2 - hB[mB] * RB[2, mB] - c2
    u_b, n_b, sub_b = e0 * t0 + e2 * t2, e0 * n0 + e2 * n2, 1
    hu = hA[ku]
    # clip the segment to |u| <= hu (sub-key 2: cut at +hu, 3: cut at -hu)
    for side in range(2):
        sgn = 1.0 if side == 0 else -1.0
        a = sgn * u_a - hu
        b = sgn * u_b - hu
        if a > 0.0 and b > 0.0:
            return 0
        if a > 0.0 or b > 0.0:
            t = a / (a - b)
            u_cut = u_a + t * (u_b - u_a)
            n_cut = n_a + t * (n_b - n_a)
            if a > 0.0:
                u_a, n_a, sub_a = u_cut, n_cut, 2 + side
            else:
                u_b, n_b, sub_b = u_cut, n_cut, 2 + side
    face_A = (kA // 2) * 2 + (0 if sA > 0 else 1)
    face_B = (kB // 2) * 2 + (0 if sB > 0 else 1)
    base = ((swap * 4 + face_A) * 4 + face_B) * 4
    # a zero extent (a capsule's end: its incident edge, or the reference edge it is cut
    # to) leaves one point, not two in one place: the deeper
    single = hB[mB] == 0.0 or hu == 0.0
    if single and n_b < n_a:
        u_a, n_a, sub_a = u_b, n_b, sub_b
    n = 0
    for k in range(2):  # (a constant count: the compiler may unroll it)
        if k == 1 and single:
            break
        pu, pn, sub = (u_a, n_a, sub_a) if k == 0 else (u_b, n_b, sub_b)
        if pn >= rA + rB + margin:
            continue
        lift = 0.5 * (rA + pn - rB)
        normal[n, 0], normal[n, 1], normal[n, 2] = sign * n0, 0.0, sign * n2
        point[n, 0] = c0 + pu * t0 + lift * n0
        point[n, 1] = xA[1]
        point[n, 2] = c2 + pu * t2 + lift * n2
        overlap[n] = rA + rB - pn
        key[n] = base + sub
        n += 1
    return n


@inner_kernel(_nrt=False)
def _nearest_corners(xi, Ri, hi, ri, xj, Rj, hj, rj, margin, out):
    """The exact deepest points, corner-edge pairs: the corners of one rectangle nearest
    the other core (the owner of the nearest corner, and its corners within round-off of
    it), key ``KEY_VERTEX + 4 owner + corner``."""
    normal, point, overlap, key = out
    best_i = best_j = np.inf
    for k in range(4):  # (a planar body's y is immaterial: each corner at the other's y)
        v0, v2 = _corner(xi, Ri, hi, k)
        best_i = min(best_i, point_box_distance(xj, Rj, hj, v0, xj[1], v2)[0])
        v0, v2 = _corner(xj, Rj, hj, k)
        best_j = min(best_j, point_box_distance(xi, Ri, hi, v0, xi[1], v2)[0])
    owner, best, tol = vertex_owner(best_i, best_j, ri, hi, rj, hj, margin)
    if owner < 0:
        return 0
    x, R, h, r_own, xo, Ro, ho, r_other, sign = owner_first(owner, xi, Ri, hi, ri, xj, Rj, hj, rj)
    n = 0
    for k in range(4):
        if not distinct_corner(h, k):
            continue
        v0, v2 = _corner(x, R, h, k)
        g, u0, _, u2, c0, _, c2 = point_box_distance(xo, Ro, ho, v0, xo[1], v2)
        if g > best + tol:
            continue
        lift = 0.5 * (r_other + g - r_own)
        normal[n, 0], normal[n, 1], normal[n, 2] = sign * u0, 0.0, sign * u2
        point[n, 0] = c0 + lift * u0
        point[n, 1] = xi[1]
        point[n, 2] = c2 + lift * u2
        overlap[n] = ri + rj - g
        key[n] = KEY_VERTEX + 4 * owner + k
        n += 1
    return n


@njit(cache=True, error_model="numpy", _nrt=False)
def rect_rect(xi, Ri, hi, ri, xj, Rj, hj, rj, margin, normal, point, overlap, key):
    """Contact manifold (up to 2 points) of two rounded rectangles i and j.

    Keys: edge contact ``((swap * 4 + face_ref) * 4 + face_inc) * 4 + sub`` (face = 2
    [axis 2] + [negative side]; sub 0, 1: a corner of the incident edge, 2, 3: the
    incident edge cut by the reference edge's side line at +u, -u); corner fallback
    ``KEY_VERTEX + 4 owner + corner``.  A face of j is the reference only if it separates
    better than i's by a round-off tolerance.
    """
    out = (normal, point, overlap, key)
    d0, d2 = xj[0] - xi[0], xj[2] - xi[2]
    reach = ri + rj + margin
    tol = 1e-9 * (max(hi[0], hi[1], hi[2]) + max(hj[0], hj[1], hj[2]) + ri + rj)
    sep_i, k_i = -np.inf, 0
    sep_j, k_j = -np.inf, 0
    for m in (0, 2):
        s = _separation(d0, d2, Ri[0, m], Ri[2, m], Ri, hi, Rj, hj)
        if s >= reach:
            return 0
        if s > sep_i:
            sep_i, k_i = s, m
        s = _separation(d0, d2, Rj[0, m], Rj[2, m], Ri, hi, Rj, hj)
        if s >= reach:
            return 0
        if s > sep_j:
            sep_j, k_j = s, m
    if sep_j > sep_i + tol:
        n = _edge_manifold(xj, Rj, hj, rj, k_j, xi, Ri, hi, ri, margin, -1.0, 1, out)
    else:
        n = _edge_manifold(xi, Ri, hi, ri, k_i, xj, Rj, hj, rj, margin, 1.0, 0, out)
    # (the four face axes are every separating axis of two rectangles: cores apart by
    # s > 0 along one of them leave no point deeper than r_i + r_j - s; cuboid.box_box)
    if manifold_is_deepest(overlap, n, ri + rj, max(sep_i, sep_j), tol):
        return n
    m = _nearest_corners(xi, Ri, hi, ri, xj, Rj, hj, rj, margin, rows_from(out, 8))
    return merge_deepest(out, n, 8, m, ri + rj, tol)


@njit(cache=True, error_model="numpy", _nrt=False)
def rect_sphere(x, R, h, r, c, radius, margin, normal, point, overlap, key):
    """Contact of a rounded box turning about y (body ``i``) with a sphere of centre ``c``
    and ``radius``: cuboid.box_sphere in a planar scene.

    A sphere is one point of contact, not an edge along y: the point is not doubled
    (multiplicity 1).  The nearest point of the core to ``c`` in the box's xz coordinates
    (clamped), and along y the core's extent ``+-h_1`` about the box's y (a sphere in the
    box's own plane is within it); the distance ``d`` from that point, overlap ``r +
    radius - d``, normal from it towards ``c``, point ``q + n (r - overlap/2)``.  A centre
    inside the core's rectangle takes the nearest edge of the rectangle (an in-plane
    normal).  Key 0.  Returns 0 or 1.
    """
    e0, e2 = c[0] - x[0], c[2] - x[2]
    q0 = e0 * R[0, 0] + e2 * R[2, 0]
    q2 = e0 * R[0, 2] + e2 * R[2, 2]
    ey = c[1] - x[1]
    oy = ey - min(max(ey, -h[1]), h[1])  # the centre beyond the core's y faces
    if abs(q0) > h[0] or abs(q2) > h[2] or oy != 0.0:
        k0 = min(max(q0, -h[0]), h[0])
        k2 = min(max(q2, -h[2]), h[2])
        c0 = x[0] + R[0, 0] * k0 + R[0, 2] * k2
        c2 = x[2] + R[2, 0] * k0 + R[2, 2] * k2
        u0, u1, u2 = c[0] - c0, oy, c[2] - c2
        d = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
        n0, n1, n2 = u0 / d, u1 / d, u2 / d
        cy = c[1] - oy
    else:  # inside: the edge of least depth
        s0, s2 = unit_sign(q0), unit_sign(q2)
        if h[0] - abs(q0) <= h[2] - abs(q2):
            d = abs(q0) - h[0]
            n0, n2 = s0 * R[0, 0], s0 * R[2, 0]
            c0, c2 = c[0] + (h[0] - abs(q0)) * n0, c[2] + (h[0] - abs(q0)) * n2  # on the face
        else:
            d = abs(q2) - h[2]
            n0, n2 = s2 * R[0, 2], s2 * R[2, 2]
            c0, c2 = c[0] + (h[2] - abs(q2)) * n0, c[2] + (h[2] - abs(q2)) * n2  # on the face
        n1 = 0.0
        cy = c[1]
    return sphere_point(d, n0, n1, n2, c0, cy, c2, r, radius, margin, normal, point, overlap, key)

"""The rounded cuboid: mass properties and contact geometry (pure per-pair numba functions).

A rounded cuboid is the Minkowski sum of a *core* box of half-extents ``h = (a, b, c)``
and a sphere of radius ``r`` (a sphero-polyhedron: Alonso-Marroquin, EPL 83, 14001
(2008); Galindo-Torres, Alonso-Marroquin et al., Phys. Rev. E 79, 060301 (2009)).  Two
rounded bodies touch where their cores come closer than the sum of their radii; at a
pair of core points at distance ``d`` the overlap is ``delta = r_i + r_j - d``.  The
outer size of the body is ``h + r``; every function here takes the core ``h``.

Frames: ``x`` (3,) is the centre [m], ``R`` (3, 3) the rotation whose columns are the
box axes in the world frame (``x_world = x + R u``), as ``Bodies.rot``.

Contact output, shared by every pair function (``M = MAX_POINTS`` rows):

* ``normal`` (M, 3): unit normal from body ``i`` to its partner ``j`` (a wall: into it);
* ``point`` (M, 3): contact point midway through the overlap [m];
* ``overlap`` (M,): ``r_i + r_j - d`` [m], > 0 in contact; points with an overlap above
  ``-margin`` are returned (so a caller sees a contact open);
* ``key`` (M,) int64: the touching feature pair, stable while that pair persists (a box
  vertex, a face pair with the clipped polygon corner, an edge pair), so that a caller can
  carry each point's shear history from step to step.

The function returns the number of points written.

Box-box contacts use the separating-axis test over the 15 axes of two boxes (3 + 3 face
normals, 9 edge cross products; Gottschalk, Lin & Manocha, SIGGRAPH 1996) on the cores:
an axis along which the cores are farther apart than ``r_i + r_j`` separates the rounded
bodies.  Otherwise the face axis of largest separation gives the reference face; the
incident face of the other box (the one most anti-parallel to its normal) is clipped
against the side planes of the reference face (Sutherland-Hodgman), and every corner of
the clipped polygon closer than ``r_i + r_j`` to the reference face is a contact point (a
face resting on a face gets the corners of their overlap, up to 8); corners closer than
:data:`COINCIDENT` of the boxes' size to each other are one point, and a corner that close
to a side plane is on it (two equally wide faces side by side, edges on side planes to
round-off: so a pair placed symmetrically about a plane has a mirror-symmetric manifold).
The deepest point of the pair is then found exactly -- the core distance of two boxes
is attained at a vertex of one (point-box distance) or between two crossing edges (the
edge axis of largest separation, closest points inside both edges; Ericson, Real-Time
Collision Detection (2005) sec. 5.1.9) -- and if the manifold misses it by more than round-off (a
vertex over a rounded edge, two crossing edges) it replaces the corner nearest to it
(which keeps its key) or, if none is within ``r_i + r_j``, is added.  An empty manifold
(e.g. two parallel edges side by side) is replaced by the deepest point, and by every
vertex within round-off of it (both ends of two parallel edges).  So the largest overlap
of every manifold is exact.  The search is skipped where the separating axes already
prove a corner exact: cores whose largest separation over the axes is ``s > 0`` (edge
axes of nearly parallel edges left out: ``separating_axes``) are at least ``s`` apart, so
a corner of overlap ``r_i + r_j - s`` is the deepest point (an edge lying on a face, a
face resting on a face: the persisting contacts of fallen dominoes).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from dominowave.dem.compiled import inline_kernel, inner_kernel

__all__ = [
    "MAX_POINTS",
    "box_box",
    "box_plane",
    "box_sphere",
    "capsule_mass_properties",
    "cuboid_mass_properties",
    "distinct_vertex",
    "manifold_is_deepest",
    "merge_deepest",
    "owner_first",
    "plane_row",
    "point_box_distance",
    "rows_from",
    "separating_axes",
    "sphere_point",
    "unit_sign",
    "vertex_owner",
]

MAX_POINTS = 25  # (at most 16 are returned; the rest is scratch)

SURE_EDGE_ANGLE = 1e-3  # edges at least this far from parallel [rad] bound the distance
# of the skip of box_box's deepest-point search (separating_axes)

COINCIDENT = 1e-6  # points of one face manifold closer than this fraction of the two
# boxes' largest half-extents are one contact (_merge_coincident), and a corner that close
# to a side plane lies on it (_clip, _beyond_side_plane)

# key offsets of the feature kinds (see box_box)
KEY_EDGE = 2 * 6 * 6 * 64
KEY_VERTEX = KEY_EDGE + 12 * 12


def cuboid_mass_properties(half_extents, density):
    """Mass [kg] and principal moments (3,) [kg m^2] of a uniform solid cuboid.

    ``half_extents`` (3,) [m] of the cuboid the body stands for (its outer size), density
    [kg/m^3]: ``m = 8 a b c rho``, ``I_x = m (b^2 + c^2) / 3`` and cyclic (a box of edge
    lengths 2a, 2b, 2c: ``m ((2b)^2 + (2c)^2) / 12``).  The principal axes are the box axes.
    """
    a, b, c = (float(v) for v in half_extents)
    mass = 8.0 * a * b * c * density
    moments = np.array([b * b + c * c, a * a + c * c, a * a + b * b]) * mass / 3.0
    return mass, moments


def capsule_mass_properties(half_length, radius, density):
    """Mass [kg] and principal moments (3,) [kg m^2] of a uniform solid capsule: a
    cylinder of radius ``r`` and length ``2 c`` (``half_length`` c [m]) closed by two
    hemispheres of radius ``r`` [m], density [kg/m^3]; its axis is body axis 2.

    With the cylinder's mass ``m_c = 2 pi r^2 c rho`` and the two hemispheres' ``m_s = 4/3
    pi r^3 rho``: ``I_2 = m_c r^2 / 2 + 2/5 m_s r^2`` about the axis, and about a diameter
    through the centre ``I_0 = I_1 = m_c (r^2 / 4 + c^2 / 3) + m_s (2/5 r^2 + c^2 + 3/4 c r)``
    (each hemisphere's moment about its centroid, ``83/320 m r^2``, shifted by the parallel
    axis theorem to its centroid at ``c + 3 r / 8`` from the centre).
    """
    c, r = float(half_length), float(radius)
    m_cyl = 2.0 * math.pi * r * r * c * density
    m_sph = 4.0 / 3.0 * math.pi * r**3 * density
    axial = 0.5 * m_cyl * r * r + 0.4 * m_sph * r * r
    diametral = m_cyl * (r * r / 4.0 + c * c / 3.0) + m_sph * (0.4 * r * r + c * c + 0.75 * c * r)
    return m_cyl + m_sph, np.array([diametral, diametral, axial])


@inline_kernel()
def unit_sign(x):
    """+1 for ``x >= 0``, else -1: the side of a point or a direction, never 0 (a point
    on the plane between two features takes the + one)."""
    return 1.0 if x >= 0.0 else -1.0


@njit(cache=True, error_model="numpy", _nrt=False)
def box_plane(x, R, h, r, p0, nw, margin, normal, point, overlap, key):
    """Contacts of a rounded box with the plane through ``p0`` of unit normal ``nw``.

    One point per core vertex ``v`` with ``d = (v - p0).nw < r + margin`` (a face resting
    on the plane gets its 4 corners): overlap ``r - d``, normal ``-nw`` (from the box into
    the wall), point ``v - nw (r - overlap / 2)``; key = the vertex id ``k`` (bit 0, 1, 2:
    the sign of the box coordinate x, y, z, 1 = positive).  A core of zero extent along
    an axis (a capsule's segment) has half as many vertices (:func:`distinct_vertex`).
    """
    n = 0
    for k in range(8):
        if not distinct_vertex(h, k):
            continue
        v0, v1, v2 = x[0], x[1], x[2]
        for m in range(3):
            s = h[m] if (k >> m) & 1 else -h[m]
            v0 += s * R[0, m]
            v1 += s * R[1, m]
            v2 += s * R[2, m]
        d = (v0 - p0[0]) * nw[0] + (v1 - p0[1]) * nw[1] + (v2 - p0[2]) * nw[2]
        if d < r + margin:
            plane_row(v0, v1, v2, d, r, -nw[0], -nw[1], -nw[2], k, n, normal, point, overlap, key)
            n += 1
    return n


@inline_kernel()
def plane_row(v0, v1, v2, d, r, m0, m1, m2, k, n, normal, point, overlap, key):
    """Row ``n`` of a plane contact of the rounded core vertex ``v`` (key ``k``) at the
    distance ``d`` [m] from the plane, ``m`` the unit normal from the body into the wall:
    overlap ``r - d``, point ``v + m (r - overlap / 2)`` (the middle of the overlap).
    The planar scenes' rows share it (:mod:`~dominowave.dem.shapes.rectangle`)."""
    delta = r - d
    reach = r - 0.5 * delta
    normal[n, 0], normal[n, 1], normal[n, 2] = m0, m1, m2
    point[n, 0] = v0 + reach * m0
    point[n, 1] = v1 + reach * m1
    point[n, 2] = v2 + reach * m2
    overlap[n] = delta
    key[n] = k


@inline_kernel()
def distinct_vertex(h, k):
    """False if vertex k of a core of half-extents ``h`` coincides with a vertex of lower
    id: a bit m of k is set where ``h[m] = 0`` (the core of a capsule is a segment, two
    vertices; of a rounded plate, a rectangle).  Each location is then one contact point,
    not two or four with their forces added."""
    return not ((k & 1 and h[0] == 0.0) or (k & 2 and h[1] == 0.0) or (k & 4 and h[2] == 0.0))


@inline_kernel()
def _vertex(x, R, h, k):
    """World position (3 floats) of vertex k of a box (bit m of k: + side of axis m)."""
    s0 = h[0] if k & 1 else -h[0]
    s1 = h[1] if k & 2 else -h[1]
    s2 = h[2] if k & 4 else -h[2]
    return (
        x[0] + s0 * R[0, 0] + s1 * R[0, 1] + s2 * R[0, 2],
        x[1] + s0 * R[1, 0] + s1 * R[1, 1] + s2 * R[1, 2],
        x[2] + s0 * R[2, 0] + s1 * R[2, 1] + s2 * R[2, 2],
    )


@njit(cache=True, error_model="numpy", _nrt=False)
def point_box_distance(x, R, h, p0, p1, p2):
    """Signed distance [m] of the point ``p`` from the solid box (centre ``x``, axes ``R``,
    half-extents ``h``): positive outside, minus the depth below the nearest face inside.
    Returns ``(distance, u0, u1, u2, c0, c1, c2)``: ``c`` the nearest surface point of
    the box, ``u`` the unit vector from ``c`` towards ``p`` (outside), or the nearest
    face's outward normal (inside)."""
    e0, e1, e2 = p0 - x[0], p1 - x[1], p2 - x[2]
    q0 = e0 * R[0, 0] + e1 * R[1, 0] + e2 * R[2, 0]
    q1 = e0 * R[0, 1] + e1 * R[1, 1] + e2 * R[2, 1]
    q2 = e0 * R[0, 2] + e1 * R[1, 2] + e2 * R[2, 2]
    if abs(q0) > h[0] or abs(q1) > h[1] or abs(q2) > h[2]:
        q0 = min(max(q0, -h[0]), h[0])
        q1 = min(max(q1, -h[1]), h[1])
        q2 = min(max(q2, -h[2]), h[2])
        c0 = x[0] + R[0, 0] * q0 + R[0, 1] * q1 + R[0, 2] * q2
        c1 = x[1] + R[1, 0] * q0 + R[1, 1] * q1 + R[1, 2] * q2
        c2 = x[2] + R[2, 0] * q0 + R[2, 1] * q1 + R[2, 2] * q2
        u0, u1, u2 = p0 - c0, p1 - c1, p2 - c2
        dist = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
        return dist, u0 / dist, u1 / dist, u2 / dist, c0, c1, c2
    # inside: the face of least depth
    d0, d1, d2 = h[0] - abs(q0), h[1] - abs(q1), h[2] - abs(q2)
    if d0 <= d1 and d0 <= d2:
        m, depth, s = 0, d0, unit_sign(q0)
        q0 = s * h[0]
    elif d1 <= d2:
        m, depth, s = 1, d1, unit_sign(q1)
        q1 = s * h[1]
    else:
        m, depth, s = 2, d2, unit_sign(q2)
        q2 = s * h[2]
    c0 = x[0] + R[0, 0] * q0 + R[0, 1] * q1 + R[0, 2] * q2
    c1 = x[1] + R[1, 0] * q0 + R[1, 1] * q1 + R[1, 2] * q2
    c2 = x[2] + R[2, 0] * q0 + R[2, 1] * q1 + R[2, 2] * q2
    return -depth, s * R[0, m], s * R[1, m], s * R[2, m], c0, c1, c2


@njit(cache=True, error_model="numpy", _nrt=False)
def box_sphere(x, R, h, r, c, radius, margin, normal, point, overlap, key):
    """Contact of a rounded box (body ``i``) with a sphere of centre ``c`` and ``radius``.

    The nearest point ``q`` of the core box to ``c`` (clamped box coordinates; inside: the
    nearest face), ``d`` the signed distance (:func:`point_box_distance`): overlap
    ``r + radius - d``, normal from ``q`` towards ``c``, point ``q + n (r - overlap/2)``.
    Key 0.  Returns 0 or 1.
    """
    d, n0, n1, n2, q0, q1, q2 = point_box_distance(x, R, h, c[0], c[1], c[2])
    return sphere_point(d, n0, n1, n2, q0, q1, q2, r, radius, margin, normal, point, overlap, key)


@inline_kernel()
def sphere_point(d, n0, n1, n2, q0, q1, q2, r, radius, margin, normal, point, overlap, key):
    """The one point of a rounded box (core point ``q`` [m] nearest to a sphere's centre,
    at signed distance ``d`` [m] along the unit normal ``n`` from ``q``; rounding ``r``)
    and a sphere of ``radius`` [m], into row 0 of the manifold arrays: overlap ``r +
    radius - d``, the point ``q + n (r - overlap/2)`` midway through the overlap, key 0.
    Returns 1, or 0 if the gap is at least ``margin`` [m]."""
    delta = r + radius - d
    if delta <= -margin:
        return 0
    reach = r - 0.5 * delta
    normal[0, 0], normal[0, 1], normal[0, 2] = n0, n1, n2
    point[0, 0] = q0 + reach * n0
    point[0, 1] = q1 + reach * n1
    point[0, 2] = q2 + reach * n2
    overlap[0] = delta
    key[0] = 0
    return 1


@inline_kernel()
def _relative_frame(xi, Ri, xj, Rj, M):
    """The frame of box j seen from box i, into the scratch rows ``M`` (at least (5, 3)):
    the direction cosines ``M[a, b] = R_i,a . R_j,b`` and the centre offset ``x_j - x_i``
    in both frames, ``M[3] = R_i^T (x_j - x_i)``, ``M[4] = R_j^T (x_j - x_i)`` (Gottschalk,
    Lin & Manocha 1996: every separating-axis projection of two boxes from these 15
    numbers)."""
    d0, d1, d2 = xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]
    for a in range(3):
        for b in range(3):
            M[a, b] = Ri[0, a] * Rj[0, b] + Ri[1, a] * Rj[1, b] + Ri[2, a] * Rj[2, b]
        M[3, a] = Ri[0, a] * d0 + Ri[1, a] * d1 + Ri[2, a] * d2
        M[4, a] = Rj[0, a] * d0 + Rj[1, a] * d1 + Rj[2, a] * d2


@inline_kernel()
def _face_gap(M, hi, hj, a, of_j):
    """Gap [m] of the two cores along face axis ``a`` of box i (``of_j`` False) or of box
    j (True) from the relative frame ``M`` (:func:`_relative_frame`): the centre offset
    along the axis less the two half-widths, e.g. ``|t_a| - (h_i,a + sum_b h_j,b |C_ab|)``;
    negative where the projections overlap."""
    if of_j:
        half = hi[0] * abs(M[0, a]) + hi[1] * abs(M[1, a]) + hi[2] * abs(M[2, a])
        return abs(M[4, a]) - (half + hj[a])
    half = hj[0] * abs(M[a, 0]) + hj[1] * abs(M[a, 1]) + hj[2] * abs(M[a, 2])
    return abs(M[3, a]) - (hi[a] + half)


@inline_kernel(python_entry=True)
def faces_separate(xi, Ri, hi, xj, Rj, hj, reach, work):
    """True if a face axis of box i or j separates the two cores by at least ``reach``
    [m]: the early exit of :func:`separating_axes` on its first six axes, in the same
    arithmetic, so that a caller may skip :func:`box_box` (no contact) without changing
    any result.  ``work``: the (2, 9, 4) scratch of box_box; ``work[0]`` keeps the
    relative frame (:func:`_relative_frame`) for ``box_box(..., frame_ready=True)``."""
    M = work[0]
    _relative_frame(xi, Ri, xj, Rj, M)
    for m in range(3):
        if _face_gap(M, hi, hj, m, False) >= reach or _face_gap(M, hi, hj, m, True) >= reach:
            return True
    return False


@inline_kernel(python_entry=True)
def separating_axes(xi, Ri, hi, xj, Rj, hj, reach, work, frame_ready=False):
    """The separating-axis test of two core boxes over their 15 axes: the 3 + 3 face
    normals and the 9 cross products of an edge of each (Gottschalk, Lin & Manocha,
    SIGGRAPH 1996), from their relative frame (:func:`_relative_frame`, in ``work[0]``).

    Returns ``(apart, sep_i, k_i, sep_j, k_j, sep_e, a, b, e0, e1, e2, sep_sure)``:
    ``apart`` if an axis separates the cores by at least ``reach`` [m] (then the rest is
    not computed); else the largest gap [m] over the face axes of i (axis ``k_i``), of j
    (``k_j``) and over the edge axes (``sep_e``, -inf if every edge pair is parallel within
    1e-6 rad: the face axes decide), with the edges ``a`` of i and ``b`` of j of that axis
    and its unit vector ``e`` (world frame) pointing from i to j; ``sep_sure`` the largest
    gap over the face axes and the edge axes of edges at least :data:`SURE_EDGE_ANGLE`
    apart (an edge axis's gap divides by its length, and so does its round-off: these
    gaps are a lower bound of the core distance to well below round-off tolerances).
    An edge axis ``R_i,a x R_j,b`` has the length ``sqrt(C_a1b^2 + C_a2b^2)`` (a1, a2 the
    other two axes of i; not ``sqrt(1 - C_ab^2)``, which cancels for nearly parallel
    edges) and projects the offset and the half-widths through the direction cosines
    ``C`` alone.  ``frame_ready``: ``work[0]`` already holds the relative frame of these
    two boxes at these positions (left there by :func:`faces_separate`), which is then not
    computed again."""
    M = work[0]
    if not frame_ready:
        _relative_frame(xi, Ri, xj, Rj, M)
    sep_i, k_i = -np.inf, 0
    sep_j, k_j = -np.inf, 0
    for m in range(3):
        s = _face_gap(M, hi, hj, m, False)
        if s >= reach:
            return True, 0.0, 0, 0.0, 0, 0.0, 0, 0, 0.0, 0.0, 0.0, 0.0
        if s > sep_i:
            sep_i, k_i = s, m
        s = _face_gap(M, hi, hj, m, True)
        if s >= reach:
            return True, 0.0, 0, 0.0, 0, 0.0, 0, 0, 0.0, 0.0, 0.0, 0.0
        if s > sep_j:
            sep_j, k_j = s, m
    sep_e, a_e, b_e, side = -np.inf, 0, 0, 1.0
    sep_sure = max(sep_i, sep_j)
    for a in range(3):
        a1, a2 = (a + 1) % 3, (a + 2) % 3
        for b in range(3):
            b1, b2 = (b + 1) % 3, (b + 2) % 3
            length = math.sqrt(M[a1, b] * M[a1, b] + M[a2, b] * M[a2, b])
            if length < 1e-6:  # (near-parallel edges: the face axes decide)
                continue
            along = M[3, a2] * M[a1, b] - M[3, a1] * M[a2, b]
            half = hi[a1] * abs(M[a2, b]) + hi[a2] * abs(M[a1, b])
            half += hj[b1] * abs(M[a, b2]) + hj[b2] * abs(M[a, b1])
            s = (abs(along) - half) / length
            if s >= reach:
                return True, 0.0, 0, 0.0, 0, 0.0, 0, 0, 0.0, 0.0, 0.0, 0.0
            if length >= SURE_EDGE_ANGLE and s > sep_sure:
                sep_sure = s
            if s > sep_e:
                sep_e, a_e, b_e, side = s, a, b, unit_sign(along)
    e0 = e1 = e2 = 0.0
    if sep_e > -np.inf:
        L0 = Ri[1, a_e] * Rj[2, b_e] - Ri[2, a_e] * Rj[1, b_e]
        L1 = Ri[2, a_e] * Rj[0, b_e] - Ri[0, a_e] * Rj[2, b_e]
        L2 = Ri[0, a_e] * Rj[1, b_e] - Ri[1, a_e] * Rj[0, b_e]
        scale = side / math.sqrt(L0 * L0 + L1 * L1 + L2 * L2)
        e0, e1, e2 = L0 * scale, L1 * scale, L2 * scale
    return False, sep_i, k_i, sep_j, k_j, sep_e, a_e, b_e, e0, e1, e2, sep_sure


@inline_kernel()
def _clip(src, n_src, dst, axis, side, limit, label, close):
    """Sutherland-Hodgman: the polygon ``src[:n_src]`` (rows u, v, n, out-edge label) cut
    by the half plane ``side * src[axis] <= limit`` into ``dst``; a new corner on the cut
    line starts an edge labelled ``label``.  A corner on the cut line -- within ``close``
    [m] of it; it counts as on the line, its coordinates are not moved -- is kept and is
    not repeated as a crossing (it becomes the corner where the edge along the cut line
    starts, if the polygon leaves the half plane there).  Returns the corner count of
    ``dst``.

    The band ``close`` matters where an edge lies along the cut line, as the side edges
    of two faces of equal width do: by round-off its ends would fall on either side, and
    the cut would put a corner anywhere along it (``a / (a - b)`` of two round-off
    errors), on one side of a symmetric pair of faces and not on the other."""
    m = 0
    first = side * src[0, axis] - limit if n_src > 0 else 0.0
    first = 0.0 if abs(first) <= close else first
    b = first
    for k in range(n_src):
        k1 = k + 1 if k + 1 < n_src else 0
        a = b  # (each corner's distance beyond the line is found once)
        if k1 == 0:
            b = first
        else:
            b = side * src[k1, axis] - limit
            b = 0.0 if abs(b) <= close else b
        if a <= 0.0:
            for col in range(4):
                dst[m, col] = src[k, col]
            m += 1
            if a == 0.0 and b > 0.0:  # (the kept corner is the crossing)
                dst[m - 1, 3] = label
                continue
        if b == 0.0:  # (the crossing is the next corner, kept on its own)
            continue
        if (a <= 0.0) != (b <= 0.0):
            t = a / (a - b)
            for col in range(3):
                dst[m, col] = src[k, col] + t * (src[k1, col] - src[k, col])
            dst[m, 3] = label if a <= 0.0 else src[k, 3]
            m += 1
    return m


@inline_kernel()
def _incident_corner(xB, RB, hB, kB, sB, k):
    """World position (3 floats) of corner k (0..3, cyclic) of face ``(kB, sB)`` of box B;
    edge k of the face runs from corner k to corner k + 1."""
    m1, m2 = (kB + 1) % 3, (kB + 2) % 3
    s1 = 1.0 if k == 0 or k == 3 else -1.0
    s2 = 1.0 if k < 2 else -1.0
    e0 = xB[0] + sB * hB[kB] * RB[0, kB] + s1 * hB[m1] * RB[0, m1] + s2 * hB[m2] * RB[0, m2]
    e1 = xB[1] + sB * hB[kB] * RB[1, kB] + s1 * hB[m1] * RB[1, m1] + s2 * hB[m2] * RB[1, m2]
    e2 = xB[2] + sB * hB[kB] * RB[2, kB] + s1 * hB[m1] * RB[2, m1] + s2 * hB[m2] * RB[2, m2]
    return e0, e1, e2


_NO_DIP = (-1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
"""What :func:`_beyond_side_plane` returns where the clipped corner is the contact."""


# (inlined: a call passes its 19 arguments, the arrays as several words each, for every
# corner where an incident edge crosses a side plane -- two per pair of fallen dominoes)
@inline_kernel()
def _beyond_side_plane(xA, RA, hA, ku, kv, c0, c1, c2, n0, n1, n2, xB, RB, hB, kB, sB, row,
                       edge, plane, close):  # fmt: skip
    """The contact that a clipped corner on a side plane stands for.

    ``row`` (u, v, height above the reference face, label) is the corner where incident
    edge ``edge`` of box B crosses side plane ``plane`` (0..3: +u, -u, +v, -v) of the
    reference face of box A (centre ``c``, outward normal ``n``, face axes ``ku``, ``kv``).
    If the edge rises beyond the plane, or its outer end (the end farther beyond the
    plane) lies within ``close`` [m] of it (the edge lies on the plane: the clipping kept
    it), the corner is the contact (the lowest point of the edge over the face; a face
    resting across an edge): returns ``(-1, ...)``.  If it dips (its outer end lower) from
    a corner above the face, the edge's nearest approach to A's core lies beyond the
    plane, over A's rounded edge: at its outer vertex (a corner sliding off the face) or
    inside the edge.  Then returns ``(vertex, t, d, u (3),
    q (3))``: the outer vertex (0..3), the position t in [0, 1] of the nearest approach
    along the edge from the corner (1: the vertex), its core distance ``d`` [m] from A, the
    unit vector ``u`` from A's nearest core point ``q`` towards it.  Beyond the side plane
    the edge is outside A's core, and its nearest approach is at its outer end or nearest
    to an edge of A's core (within a face region the distance is linear along the edge):
    the vertex, or the nearest of the 12 segment-segment closest points (Ericson 2005,
    sec. 5.1.9).

    So the manifold is continuous where a vertex of the incident face crosses a side
    plane: the clipped polygon trades the vertex for two corners on the plane, at its
    depth at that instant; a dipping edge's corner is replaced by the vertex again (with
    the vertex's key, once for both edges), which keeps its exact distance (over the
    rounded edge) and its shear history.
    """
    axis = plane // 2
    side = 1.0 if plane % 2 == 0 else -1.0
    limit = hA[ku] if axis == 0 else hA[kv]
    vertex = edge
    a0, a1, a2 = _incident_corner(xB, RB, hB, kB, sB, edge)
    b0, b1, b2 = _incident_corner(xB, RB, hB, kB, sB, (edge + 1) % 4)
    k_axis = ku if axis == 0 else kv
    d0, d1, d2 = RA[0, k_axis], RA[1, k_axis], RA[2, k_axis]
    beyond_a = side * ((a0 - c0) * d0 + (a1 - c1) * d1 + (a2 - c2) * d2) - limit
    beyond_b = side * ((b0 - c0) * d0 + (b1 - c1) * d1 + (b2 - c2) * d2) - limit
    if beyond_b > beyond_a:  # the edge's outer end is corner edge + 1
        vertex = (edge + 1) % 4
        a0, a1, a2 = b0, b1, b2
    # An edge lying on the side plane (an edge of a face as wide as the reference face, or
    # beside it) does not leave the face, whichever end round-off puts farther out.  Taken
    # for a dip, its corner would become the other end of the edge, already a corner of
    # the polygon, and one end of the line contact would vanish -- on one side of a
    # symmetric pair, a torque from nothing that tips a symmetric chain out of its plane.
    if max(beyond_a, beyond_b) <= close:
        return _NO_DIP
    height = (a0 - c0) * n0 + (a1 - c1) * n1 + (a2 - c2) * n2
    if height >= row[2] or row[2] <= 0.0:  # (at or below the face: the edge enters A's core)
        return _NO_DIP
    # the crossing p in world coordinates, the edge beyond it p + t g, t in [0, 1]
    p0 = c0 + row[0] * RA[0, ku] + row[1] * RA[0, kv] + row[2] * n0
    p1 = c1 + row[0] * RA[1, ku] + row[1] * RA[1, kv] + row[2] * n1
    p2 = c2 + row[0] * RA[2, ku] + row[1] * RA[2, kv] + row[2] * n2
    g0, g1, g2 = a0 - p0, a1 - p1, a2 - p2
    end = point_box_distance(xA, RA, hA, a0, a1, a2)
    t = 1.0
    for e in range(12 if g0 * g0 + g1 * g1 + g2 * g2 > 0.0 else 0):  # nearest to A's edges
        ax, k1, k2 = e // 4, (e // 4 + 1) % 3, (e // 4 + 2) % 3
        s1 = hA[k1] if e & 2 else -hA[k1]
        s2 = hA[k2] if e & 1 else -hA[k2]
        q0 = xA[0] + s1 * RA[0, k1] + s2 * RA[0, k2]
        q1 = xA[1] + s1 * RA[1, k1] + s2 * RA[1, k2]
        q2 = xA[2] + s1 * RA[2, k1] + s2 * RA[2, k2]
        m0, m1, m2 = p0 + 0.5 * g0 - q0, p1 + 0.5 * g1 - q1, p2 + 0.5 * g2 - q2
        sm, _ = _segment_closest(
            m0, m1, m2, 0.5 * g0, 0.5 * g1, 0.5 * g2,
            hA[ax] * RA[0, ax], hA[ax] * RA[1, ax], hA[ax] * RA[2, ax],
        )  # fmt: skip
        te = 0.5 * (1.0 + sm)
        near = point_box_distance(xA, RA, hA, p0 + te * g0, p1 + te * g1, p2 + te * g2)
        if near[0] < end[0]:
            end, t = near, te
    if end[0] <= 1e-9 * (hA[0] + hA[1] + hA[2]):  # (touching A's core: no normal)
        return _NO_DIP
    return float(vertex), t, end[0], end[1], end[2], end[3], end[4], end[5], end[6]


@njit(cache=True, error_model="numpy", _nrt=False)
def _face_manifold(xA, RA, hA, rA, kA, xB, RB, hB, rB, margin, sign, swap, work, out):
    """Clip the incident face of box B against the reference face ``kA`` of box A.

    ``out = (normal, point, overlap, key)``; the normal written is ``sign`` times the
    reference face's outward normal (so that it points from body i to body j);
    ``swap`` = 1 if A is body j.  Returns the number of points.
    """
    normal, point, overlap, key = out
    d0, d1, d2 = xB[0] - xA[0], xB[1] - xA[1], xB[2] - xA[2]
    sA = unit_sign(d0 * RA[0, kA] + d1 * RA[1, kA] + d2 * RA[2, kA])
    n0, n1, n2 = sA * RA[0, kA], sA * RA[1, kA], sA * RA[2, kA]
    ku, kv = (kA + 1) % 3, (kA + 2) % 3
    c0 = xA[0] + hA[kA] * n0
    c1 = xA[1] + hA[kA] * n1
    c2 = xA[2] + hA[kA] * n2
    # incident face: the face of B whose outward normal is most anti-parallel to n
    kB = 0
    best = -1.0
    for m in range(3):
        dot = abs(n0 * RB[0, m] + n1 * RB[1, m] + n2 * RB[2, m])
        if dot > best:
            best = dot
            kB = m
    sB = -unit_sign(n0 * RB[0, kB] + n1 * RB[1, kB] + n2 * RB[2, kB])
    poly = work[0]
    for k in range(4):  # corners in cyclic order; edge k runs from corner k to k + 1
        e0, e1, e2 = _incident_corner(xB, RB, hB, kB, sB, k)
        e0, e1, e2 = e0 - c0, e1 - c1, e2 - c2
        poly[k, 0] = e0 * RA[0, ku] + e1 * RA[1, ku] + e2 * RA[2, ku]
        poly[k, 1] = e0 * RA[0, kv] + e1 * RA[1, kv] + e2 * RA[2, kv]
        poly[k, 2] = e0 * n0 + e1 * n1 + e2 * n2
        poly[k, 3] = k
    count = 4
    src, dst = work[0], work[1]
    close = COINCIDENT * (max(hA[0], hA[1], hA[2]) + max(hB[0], hB[1], hB[2]))
    for plane in range(4):  # side planes: +u, -u, +v, -v, labels 4..7
        axis = plane // 2
        side = 1.0 if plane % 2 == 0 else -1.0
        limit = hA[ku] if axis == 0 else hA[kv]
        count = _clip(src, count, dst, axis, side, limit, 4 + plane, close)
        src, dst = dst, src
        if count == 0:
            return 0
    face_A = 2 * kA + (0 if sA > 0 else 1)
    face_B = 2 * kB + (0 if sB > 0 else 1)
    base = ((swap * 6 + face_A) * 6 + face_B) * 64
    flat = _no_area(hA, kA)
    reach = rA + rB + margin
    n = 0
    for k in range(count):
        pn = src[k, 2]
        label_in = int(src[k - 1 if k > 0 else count - 1, 3])
        label_out = int(src[k, 3])
        near = -1  # (the incident vertex within `close` of a crossing)
        if (label_in < 4) != (label_out < 4):  # a side-plane crossing of an incident edge
            edge = min(label_in, label_out)
            plane = max(label_in, label_out) - 4
            near = _vertex_within(xB, RB, hB, kB, sB, edge, c0, c1, c2, RA, ku, kv, n0, n1, n2,
                                  src[k], close)  # fmt: skip
            # (a face without area -- a capsule's side -- has no side planes to dip beyond:
            # its clipped corners are exact, their height over it their core distance)
            w = _NO_DIP
            if not flat:
                w = _beyond_side_plane(
                    xA, RA, hA, ku, kv, c0, c1, c2, n0, n1, n2, xB, RB, hB, kB, sB, src[k],
                    edge, plane, close,
                )  # fmt: skip
            if w[0] >= 0:  # the incident edge dips beyond the side plane
                t, d, u0, u1, u2, q0, q1, q2 = w[1], w[2], w[3], w[4], w[5], w[6], w[7], w[8]
                if d >= reach:
                    continue
                vertex = int(w[0])
                label_in, label_out = vertex - 1 if vertex > 0 else 3, vertex
                if t < 1.0 and near < 0:  # (inside the edge: the crossing's own key)
                    label_in, label_out = edge, plane + 4
                corner = _corner_key(base, label_in, label_out, False)
                duplicate = False
                for c in range(n):
                    duplicate = duplicate or key[c] == corner
                if duplicate:  # (both edges of the vertex dip to it)
                    continue
                lift = 0.5 * (rA + d - rB)
                point[n, 0] = q0 + lift * u0
                point[n, 1] = q1 + lift * u1
                point[n, 2] = q2 + lift * u2
                normal[n, 0], normal[n, 1], normal[n, 2] = sign * u0, sign * u1, sign * u2
                overlap[n] = rA + rB - d
                key[n] = corner
                n += 1
                continue
        if pn >= reach:
            continue
        if label_in == label_out:  # (a polygon cut down to one corner on a side plane)
            for edge in (0, 2):
                if near < 0:
                    near = _vertex_within(xB, RB, hB, kB, sB, edge, c0, c1, c2, RA, ku, kv, n0,
                                          n1, n2, src[k], close)  # fmt: skip
        if near >= 0:  # (a crossing at a vertex, or the vertex alone)
            label_in, label_out = near - 1 if near > 0 else 3, near
        lift = 0.5 * (rA + pn - rB)  # midway between the two rounded surfaces
        point[n, 0] = c0 + src[k, 0] * RA[0, ku] + src[k, 1] * RA[0, kv] + lift * n0
        point[n, 1] = c1 + src[k, 0] * RA[1, ku] + src[k, 1] * RA[1, kv] + lift * n1
        point[n, 2] = c2 + src[k, 0] * RA[2, ku] + src[k, 1] * RA[2, kv] + lift * n2
        normal[n, 0], normal[n, 1], normal[n, 2] = sign * n0, sign * n1, sign * n2
        overlap[n] = rA + rB - pn
        key[n] = _corner_key(base, label_in, label_out, flat)
        n += 1
    return _merge_coincident(out, n, base, close)


@inline_kernel()
def _no_area(h, k):
    """True if the face of axis k of a core of half-extents ``h`` has no area (an
    in-plane extent 0: a capsule's side is a segment, its end a point)."""
    return h[(k + 1) % 3] == 0.0 or h[(k + 2) % 3] == 0.0


@inline_kernel()
def _corner_key(base, label_in, label_out, flat):
    """Key of a clipped corner where the polygon edges ``label_in``, ``label_out`` meet:
    ``base + 8 lo + hi`` of the two labels.  On a reference face without area (``flat``:
    a capsule's side, a segment) the polygon is cut down to a segment whose two ends meet
    the same two labels in opposite order: the key keeps the order, ``base + 8 in + out``,
    so that the two ends are two points."""
    if flat:
        return base + label_in * 8 + label_out
    return base + min(label_in, label_out) * 8 + max(label_in, label_out)


@inline_kernel()
def _vertex_within(xB, RB, hB, kB, sB, edge, c0, c1, c2, RA, ku, kv, n0, n1, n2, row, close):
    """The end (corner 0..3) of incident edge ``edge`` within ``close`` [m] of the clipped
    corner ``row`` (u, v, height over the reference face of centre ``c``), or -1: a
    crossing that close to a vertex is that vertex, and takes its key."""
    q0 = c0 + row[0] * RA[0, ku] + row[1] * RA[0, kv] + row[2] * n0
    q1 = c1 + row[0] * RA[1, ku] + row[1] * RA[1, kv] + row[2] * n1
    q2 = c2 + row[0] * RA[2, ku] + row[1] * RA[2, kv] + row[2] * n2
    for end in range(2):
        corner = (edge + end) % 4
        e0, e1, e2 = _incident_corner(xB, RB, hB, kB, sB, corner)
        if (e0 - q0) ** 2 + (e1 - q1) ** 2 + (e2 - q2) ** 2 < close * close:
            return corner
    return -1


@inner_kernel(_nrt=False)
def _merge_coincident(out, n, base, close):
    """Merge the points of one face manifold ``out[:n]`` that lie within ``close`` [m] of
    each other, or have the same key, into one; returns the new count.

    The clipping lists one contact location twice where an incident corner lies on a
    side plane: a vertex kept just inside, or replaced just beyond by the vertex of its
    dipping edge, next to the corner where its other edge crosses the plane.  Two faces
    of equal width side by side (a chain of dominoes, their edges aligned to round-off)
    are that configuration all along, and round-off decides, step by step, whether the
    corner is one point or two; each copy doubles the corner's stiffness and brings its
    elastic energy with it.  The merged point is the deeper of the two (the exact one of
    the pair) and keeps the key of the incident vertex if either is one (a corner key
    ``base + 8 lo + hi`` with ``hi < 4``: a box's keys have ``lo <= hi``, so both labels
    are incident edges), so the key persists whichever side of the plane round-off puts
    the vertex on.  The ordered keys of a face without area (:func:`_corner_key`) are
    read the same way, so there a crossing may keep its key over a vertex's; the
    continuation by distance (boxes._continued_row) carries the shear history either
    way."""
    _, point, overlap, key = out
    m = 0
    for k in range(n):
        twin = -1
        for c in range(m):
            g2 = 0.0
            for d in range(3):
                g2 += (point[c, d] - point[k, d]) ** 2
            if g2 < close * close or key[c] == key[k]:
                twin = c
                break
        if twin < 0:
            if m < k:  # (a point before it was merged: move it up)
                _copy_row(out, k, m)
            m += 1
            continue
        kept = key[twin]
        if (key[k] - base) % 8 < 4 and (kept - base) % 8 >= 4:  # (k is an incident vertex)
            kept = key[k]
        if overlap[k] > overlap[twin]:
            _copy_row(out, k, twin)
        key[twin] = kept
    return m


@inline_kernel()
def _edge_id(R, n0, n1, n2, a, s):
    """Signs ``(s1, s2)`` along the axes a+1, a+2 and id (0..11) of the edge along axis
    ``a`` of a box that lies farthest along ``s n``: id = 4 a + 2 [s1 > 0] + [s2 > 0]."""
    k1, k2 = (a + 1) % 3, (a + 2) % 3
    s1 = unit_sign(s * (n0 * R[0, k1] + n1 * R[1, k1] + n2 * R[2, k1]))
    s2 = unit_sign(s * (n0 * R[0, k2] + n1 * R[1, k2] + n2 * R[2, k2]))
    return s1, s2, 4 * a + (2 if s1 > 0 else 0) + (1 if s2 > 0 else 0)


@inline_kernel()
def _segment_closest(r0, r1, r2, u0, u1, u2, v0, v1, v2):
    """Parameters (s, t) of the closest points ``p + s u``, ``q + t v`` of two segments with
    s, t in [-1, 1] (``u``, ``v`` half-length vectors, ``r = p - q``; Ericson 2005, sec.
    5.1.9).  A segment of zero length (the edge of a zero extent, a capsule's) gives a
    NaN parameter: ``v`` gives ``t`` NaN and ``s = 0``, ``u`` (if ``t`` is clamped) ``s``
    NaN.  The edge-edge contact rejects both (the vertex search finds such a pair), and
    the dip beyond a side plane, which uses ``s`` of a zero-length ``v``, takes the
    midpoint as a candidate."""
    a = u0 * u0 + u1 * u1 + u2 * u2
    e = v0 * v0 + v1 * v1 + v2 * v2
    b = u0 * v0 + u1 * v1 + u2 * v2
    c = u0 * r0 + u1 * r1 + u2 * r2
    f = v0 * r0 + v1 * r1 + v2 * r2
    denom = a * e - b * b
    s = min(max((b * f - c * e) / denom, -1.0), 1.0) if denom > 0.0 else 0.0
    t = (b * s + f) / e
    if t < -1.0 or t > 1.0:
        t = min(max(t, -1.0), 1.0)
        s = min(max((t * b - c) / a, -1.0), 1.0)
    return s, t


@inner_kernel(_nrt=False)
def _edge_manifold(xi, Ri, hi, ri, a, xj, Rj, hj, rj, b, n0, n1, n2, sep, margin, out):
    """One point between the closest points of edge ``a`` of box i (farthest along n) and
    edge ``b`` of box j (farthest along -n).  Separated cores: the distance of the two
    segments; penetrating cores: the separation ``sep`` along the axis ``n``."""
    normal, point, overlap, key = out
    s1, s2, id_i = _edge_id(Ri, n0, n1, n2, a, 1.0)
    t1, t2, id_j = _edge_id(Rj, n0, n1, n2, b, -1.0)
    ai1, ai2 = (a + 1) % 3, (a + 2) % 3
    bj1, bj2 = (b + 1) % 3, (b + 2) % 3
    # edge centres p, q and half-length vectors u, v
    p0 = xi[0] + s1 * hi[ai1] * Ri[0, ai1] + s2 * hi[ai2] * Ri[0, ai2]
    p1 = xi[1] + s1 * hi[ai1] * Ri[1, ai1] + s2 * hi[ai2] * Ri[1, ai2]
    p2 = xi[2] + s1 * hi[ai1] * Ri[2, ai1] + s2 * hi[ai2] * Ri[2, ai2]
    q0 = xj[0] + t1 * hj[bj1] * Rj[0, bj1] + t2 * hj[bj2] * Rj[0, bj2]
    q1 = xj[1] + t1 * hj[bj1] * Rj[1, bj1] + t2 * hj[bj2] * Rj[1, bj2]
    q2 = xj[2] + t1 * hj[bj1] * Rj[2, bj1] + t2 * hj[bj2] * Rj[2, bj2]
    u0, u1, u2 = hi[a] * Ri[0, a], hi[a] * Ri[1, a], hi[a] * Ri[2, a]
    v0, v1, v2 = hj[b] * Rj[0, b], hj[b] * Rj[1, b], hj[b] * Rj[2, b]
    s, t = _segment_closest(p0 - q0, p1 - q1, p2 - q2, u0, u1, u2, v0, v1, v2)
    if not (-1.0 < s < 1.0 and -1.0 < t < 1.0):
        return 0  # (the closest points involve a vertex: a face or vertex contact)
    p0, p1, p2 = p0 + s * u0, p1 + s * u1, p2 + s * u2
    q0, q1, q2 = q0 + t * v0, q1 + t * v1, q2 + t * v2
    g0, g1, g2 = q0 - p0, q1 - p1, q2 - p2
    dist = math.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
    if sep > 0.0 and dist > 0.0:
        n0, n1, n2 = g0 / dist, g1 / dist, g2 / dist
    else:
        dist = sep
    delta = ri + rj - dist
    if delta <= -margin:
        return 0
    lift = 0.5 * (ri + dist - rj)
    normal[0, 0], normal[0, 1], normal[0, 2] = n0, n1, n2
    point[0, 0] = p0 + lift * n0
    point[0, 1] = p1 + lift * n1
    point[0, 2] = p2 + lift * n2
    overlap[0] = delta
    key[0] = KEY_EDGE + id_i * 12 + id_j
    return 1


@inline_kernel()
def vertex_owner(best_i, best_j, ri, hi, rj, hj, margin):
    """``(owner, best, tol)`` of the nearest-vertex contact of two rounded boxes (or
    rectangles) i and j, given the least core distance [m] of a vertex of each to the
    other core: the body whose vertex is nearer (0: i, 1: j; i owns a tie within ``tol``,
    a vertex on a vertex; -1 if the pair is out of reach, the gap beyond ``margin``), the
    least distance [m], and the round-off tolerance [m] of a tie."""
    best = min(best_i, best_j)
    if ri + rj - best <= -margin:
        return -1, best, 0.0
    tol = 1e-9 * (ri + rj + max(hi[0], hi[1], hi[2]) + max(hj[0], hj[1], hj[2]))
    return (0 if best_i <= best + tol else 1), best, tol


@inline_kernel()
def owner_first(owner, xi, Ri, hi, ri, xj, Rj, hj, rj):
    """The two bodies of a nearest-vertex contact, the owner of the vertex first:
    ``(x, R, h, r)`` of the owner, the same of the other, and the sign that turns the
    normal from i to j into the normal towards the vertex (-1 if i owns it)."""
    if owner == 0:
        return xi, Ri, hi, ri, xj, Rj, hj, rj, -1.0
    return xj, Rj, hj, rj, xi, Ri, hi, ri, 1.0


@inner_kernel(_nrt=False)
def _nearest_vertices(xi, Ri, hi, ri, xj, Rj, hj, rj, margin, out):
    """The vertices of one box nearest the other core, as contact points: the box owning
    the vertex of least distance, and its vertices within a round-off tolerance of it (a
    symmetric pair of parallel edges gives both ends); key ``KEY_VERTEX + 8 owner + k``.
    Returns the number of points (0 if out of reach)."""
    normal, point, overlap, key = out
    best_i = best_j = np.inf
    for k in range(8):
        v0, v1, v2 = _vertex(xi, Ri, hi, k)
        best_i = min(best_i, point_box_distance(xj, Rj, hj, v0, v1, v2)[0])
        v0, v1, v2 = _vertex(xj, Rj, hj, k)
        best_j = min(best_j, point_box_distance(xi, Ri, hi, v0, v1, v2)[0])
    owner, best, tol = vertex_owner(best_i, best_j, ri, hi, rj, hj, margin)
    if owner < 0:
        return 0
    x, R, h, r_own, xo, Ro, ho, r_other, sign = owner_first(owner, xi, Ri, hi, ri, xj, Rj, hj, rj)
    n = 0
    for k in range(8):
        if not distinct_vertex(h, k):
            continue
        v0, v1, v2 = _vertex(x, R, h, k)
        g, u0, u1, u2, c0, c1, c2 = point_box_distance(xo, Ro, ho, v0, v1, v2)
        if g > best + tol:
            continue
        lift = 0.5 * (r_other + g - r_own)  # from the other core's surface point
        normal[n, 0], normal[n, 1], normal[n, 2] = sign * u0, sign * u1, sign * u2
        point[n, 0] = c0 + lift * u0
        point[n, 1] = c1 + lift * u1
        point[n, 2] = c2 + lift * u2
        overlap[n] = ri + rj - g
        key[n] = KEY_VERTEX + 8 * owner + k
        n += 1
    return n


@inline_kernel()
def rows_from(out, k):
    """The output arrays from row k on."""
    return out[0][k:], out[1][k:], out[2][k:], out[3][k:]


@inline_kernel()
def _copy_row(out, src, dst):
    for d in range(3):
        out[0][dst, d] = out[0][src, d]
        out[1][dst, d] = out[1][src, d]
    out[2][dst] = out[2][src]
    out[3][dst] = out[3][src]


@njit(cache=True, error_model="numpy", _nrt=False)
def box_box(
    xi, Ri, hi, ri, xj, Rj, hj, rj, margin, work, normal, point, overlap, key, frame_ready=False
):
    """Contact manifold of two rounded boxes i and j (see the module docstring).

    ``work``: (2, 9, 4) float64 scratch (relative frame, clipping buffers); with
    ``frame_ready``, ``work[0]`` holds the relative frame of the two boxes already, as
    :func:`faces_separate` leaves it (the engine's bounding test, ``within_reach`` of
    boxes._box_geometry, calls that just before; the frame is the same arithmetic either
    way).  Keys: face contact ``((swap * 6 + face_ref) * 6 + face_inc) * 64 + corner``
    (face = 2 axis + [negative side], swap = 1 if the reference face is j's, corner = the
    pair of polygon edge labels meeting there: incident edges 0..3, reference side planes
    4..7); edge contact
    ``KEY_EDGE + 12 edge_i + edge_j``; vertex ``KEY_VERTEX + 8 owner + vertex``.  A face of
    j is the reference only if it separates better than every face of i by a round-off
    tolerance (so that ties -- parallel faces -- keep one choice).
    """
    out = (normal, point, overlap, key)
    tol = 1e-9 * (max(hi[0], hi[1], hi[2]) + max(hj[0], hj[1], hj[2]) + ri + rj)
    apart, sep_i, k_i, sep_j, k_j, sep_e, a_e, b_e, e0, e1, e2, sure = separating_axes(
        xi, Ri, hi, xj, Rj, hj, ri + rj + margin, work, frame_ready
    )
    if apart:
        return 0
    if sep_j > sep_i + tol:
        n = _face_manifold(xj, Rj, hj, rj, k_j, xi, Ri, hi, ri, margin, -1.0, 1, work, out)
    else:
        n = _face_manifold(xi, Ri, hi, ri, k_i, xj, Rj, hj, rj, margin, 1.0, 0, work, out)
    # The exact deepest point: the core distance of two boxes is attained at a vertex
    # (point-box distance) or between two crossing edges.
    if manifold_is_deepest(overlap, n, ri + rj, sure, tol):
        return n
    v_row, e_row = 16, 24
    m_v = _nearest_vertices(xi, Ri, hi, ri, xj, Rj, hj, rj, margin, rows_from(out, v_row))
    m_e = 0
    if sep_e > -np.inf:
        m_e = _edge_manifold(
            xi, Ri, hi, ri, a_e, xj, Rj, hj, rj, b_e, e0, e1, e2, sep_e, margin,
            rows_from(out, e_row),
        )  # fmt: skip
    if m_e == 1 and (m_v == 0 or overlap[e_row] > overlap[v_row]):
        first, count = e_row, 1
    else:
        first, count = v_row, m_v
    return merge_deepest(out, n, first, count, ri + rj, tol)


@inline_kernel(python_entry=True)
def manifold_is_deepest(overlap, n, reach, separation, tol):
    """True if the manifold ``overlap[:n]`` is not empty and no point of the pair can be
    deeper than it by more than ``tol / 2``: ``separation`` > 0 a gap of the cores'
    projections on an axis (``separating_axes``' ``sep_sure``), ``reach`` = ``r_i + r_j``.
    Cores that far apart along an axis are at least ``separation`` apart, so no point is
    deeper than ``reach - separation``; then :func:`merge_deepest` would leave the manifold
    as it is, and the exact deepest point need not be computed (a face resting on a face,
    an edge lying on a face)."""
    if n == 0 or separation <= 0.0:
        return False
    deepest = -np.inf
    for k in range(n):
        deepest = max(deepest, overlap[k])
    return reach - separation <= deepest + 0.5 * tol


@inner_kernel(_nrt=False)
def merge_deepest(out, n, first, count, reach, tol):
    """Merge the exact deepest points (rows ``first .. first + count - 1``, equally deep)
    into the manifold ``out[:n]``; returns the new count.  An empty manifold becomes the
    deepest points.  Otherwise, if they are deeper than every corner by more than ``tol``
    [m] (the manifold misses a vertex over a rounded edge, or two crossing edges), each
    replaces the corner nearest to it (keeping the corner's key, so its history) if that
    is within ``reach`` [m], or is added."""
    _, point, overlap, key = out
    if count == 0:
        return n
    if n == 0:
        for k in range(count):
            _copy_row(out, first + k, k)
        return count
    deepest = -np.inf
    for k in range(n):
        deepest = max(deepest, overlap[k])
    if overlap[first] <= deepest + tol:
        return n
    n_old = n
    for c in range(first, first + count):
        nearest, gap2 = -1, reach * reach
        for k in range(n_old):
            g2 = 0.0
            for d in range(3):
                g2 += (point[k, d] - point[c, d]) ** 2
            if g2 < gap2:
                nearest, gap2 = k, g2
        if nearest >= 0:
            corner_key = key[nearest]
            _copy_row(out, c, nearest)
            key[nearest] = corner_key
        else:
            _copy_row(out, c, n)
            n += 1
    return n

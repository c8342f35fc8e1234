"""Sphere contacts: the Verlet list and the force driver.

The driver :func:`compute_forces` maps the sphere's pair geometry (shapes/sphere.py:
sphere_sphere and sphere_wall, the normal and overlap; contact_point) over the Verlet
list, hands each contact point to the one law of every contact point of the engine
(laws/point.py: the linear spring-dashpot of laws/linear.py with the Coulomb-limited
shear spring of laws/tangential.py), and writes each pair's row of the contact table
(point, normal, the law's state), which the bookkeeping of every table reads
(contact_rows.py) (:func:`compute_forces_planar`, the same source compiled for a planar
scene: :func:`_sphere_driver`).  A listed pair's constants come from its materials
(:func:`pair_properties`, by material_pairs.material_pair).

Sign convention: the unit normal ``n`` points from sphere ``i`` to its partner ``j``; the
returned force acts on ``j`` (``-F`` on ``i``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from dominowave.dem.compiled import inline_kernel, inner_kernel
from dominowave.dem.contact_rows import (
    END,
    ONSET,
    copy_row,
    event_lag,
    lever_arm,
    log_change,
    point_velocity,
)
from dominowave.dem.energy import LEDGER_FRICTION
from dominowave.dem.integrate import ROT_NONE
from dominowave.dem.laws.linear import end_impulse, viscous_coefficient
from dominowave.dem.laws.point import point_law
from dominowave.dem.laws.tangential import SHEAR_YADE, yade_shear_velocity
from dominowave.dem.material_pairs import material_pair
from dominowave.dem.shapes.sphere import contact_point, sphere_sphere, sphere_wall

__all__ = [
    "apply_at_lever",
    "apply_in_plane",
    "begin_contact",
    "build_verlet_list",
    "compute_forces",
    "compute_forces_planar",
    "end_contact",
    "idle_pair",
    "mark_build",
    "needs_rebuild",
    "needs_rebuild_after_drift",
    "point_velocity_in_plane",
]


@njit(cache=True, error_model="numpy", _nrt=False)
def pair_properties(si, sj_or_wall, spheres, walls, bodies, mats, out):
    """kn, kt, mu, cn of a candidate pair into ``out[0:4]``: the properties of its
    material pair (material_pairs.material_pair) and the dashpot of the restitution for
    the two bodies' reduced mass (laws.linear.viscous_coefficient; YADE's convention,
    translation only).  A body that a normal force at the sphere cannot move
    (:func:`_immovable`) takes no share: the partner's own mass, as against a wall (such a
    body against a wall or another: no dashpot, there is no impact to damp)."""
    mi = spheres.material[si]
    Ri = spheres.radius[si]
    bi = spheres.body[si]
    m_eff = bodies.mass[bi]
    if sj_or_wall >= 0:
        mj = spheres.material[sj_or_wall]
        Rj = spheres.radius[sj_or_wall]
        bj = spheres.body[sj_or_wall]
        fixed_i, fixed_j = _immovable(bodies, spheres, si), _immovable(bodies, spheres, sj_or_wall)
        if fixed_i and fixed_j:
            m_eff = 0.0
        elif fixed_i:
            m_eff = bodies.mass[bj]
        elif not fixed_j:
            m_eff = bodies.mass[bi] * bodies.mass[bj] / (bodies.mass[bi] + bodies.mass[bj])
    else:
        mj = walls.material[-sj_or_wall - 1]
        Rj = Ri  # a wall takes the radius of the sphere touching it
        if _immovable(bodies, spheres, si):
            m_eff = 0.0
    material_pair(mats, mi, Ri, mj, Rj, out)
    out[3] = viscous_coefficient(out[3], m_eff, out[0])


@inline_kernel()
def _immovable(bodies, spheres, s):
    """True if a normal force on sphere s cannot move its body: the body's three
    translations are blocked, and it cannot turn (rot_mode ROT_NONE) or the sphere sits at
    its centre of mass (a normal force on it has no lever).  A clump pinned at its centre
    of mass but free to turn is not immovable: it keeps its own mass."""
    b = spheres.body[s]
    blocked = bodies.blocked[b]
    if blocked[0] == 0 or blocked[1] == 0 or blocked[2] == 0:
        return False
    local = spheres.local[s]
    return bodies.rot_mode[b] == ROT_NONE or local[0] == local[1] == local[2] == 0.0


# --------------------------------------------------------------------------- neighbours


@njit(cache=True, error_model="numpy", _nrt=False)
def needs_rebuild(bodies, skin, n_candidates):
    """True if a member sphere of some body may have moved more than skin/2 since the last
    Verlet-list build.

    Tested per body, not per sphere: a sphere at ``x + R u`` moves by at most
    ``|x - x0| + |R - R0| |u|``, and the spectral norm of ``R - R0`` is ``2 sin(theta/2)``
    for the angle theta of the rotation between the two orientations; ``|u| <= extent``.
    With ``d = |q - q0|`` (q0 taken with the sign that makes ``q . q0 >= 0``),
    ``d = 2 sin(theta/4)`` and ``sin(theta/2) = d sqrt(1 - d^2/4)``, free of the
    cancellation of ``sqrt(1 - (q . q0)^2)`` at small angles.  The bound is attained by
    a sphere at distance ``extent`` moving along the translation, so the list is rebuilt no
    earlier than a per-sphere test would; the forces do not depend on when it is (inactive
    pairs contribute nothing, active pairs are kept in key order).
    """
    if n_candidates < 0:
        return True
    half = 0.5 * skin
    for b in range(bodies.pos.shape[0]):
        if moved_beyond(bodies, b, half):
            return True
    return False


@inner_kernel(_nrt=False)
def needs_rebuild_after_drift(bodies, skin, n_candidates, first, stop):
    """:func:`needs_rebuild` after a drift of the bodies that are not held, all among
    ``first .. stop - 1``: only those are tested.  A held body has not moved since the
    test after its last drift, which found it within skin/2 of its place at the last
    build (or the list was rebuilt); the first step of a run tests every body."""
    if n_candidates < 0:
        return True
    half = 0.5 * skin
    held = bodies.held
    for b in range(first, stop):
        if not held[b] and moved_beyond(bodies, b, half):
            return True
    return False


@inline_kernel()
def moved_beyond(bodies, b, limit):
    """True if a member sphere of body b may have moved more than ``limit`` [m] since the
    last Verlet-list build (the bound of :func:`needs_rebuild`)."""
    pos, pos0, quat, quat0 = bodies.pos, bodies.pos_at_build, bodies.quat, bodies.quat_at_build
    dx = pos[b, 0] - pos0[b, 0]
    dy = pos[b, 1] - pos0[b, 1]
    dz = pos[b, 2] - pos0[b, 2]
    dot = quat[b, 0] * quat0[b, 0] + quat[b, 1] * quat0[b, 1]
    dot += quat[b, 2] * quat0[b, 2] + quat[b, 3] * quat0[b, 3]
    sign = 1.0 if dot >= 0.0 else -1.0
    d2 = 0.0
    for k in range(4):
        diff = quat[b, k] - sign * quat0[b, k]
        d2 += diff * diff
    shift2 = dx * dx + dy * dy + dz * dz
    sin_half2 = d2 * max(0.0, 1.0 - 0.25 * d2)
    extent = bodies.extent[b]
    # (a + b)^2 <= 2 (a^2 + b^2): most bodies are decided without a square root (with a
    # margin, so that rounding cannot contradict the exact test below)
    if 2.0 * (shift2 + 4.0 * sin_half2 * extent * extent) < 0.99 * limit * limit:
        return False
    return math.sqrt(shift2) + 2.0 * math.sqrt(sin_half2) * extent > limit


@njit(cache=True, error_model="numpy")
def _candidate_pairs(spheres, walls, skin, active=None):
    """All sphere-sphere (different bodies) and sphere-wall pairs closer than the skin;
    with ``active`` ((ns,) uint8), only those with an active sphere (two spheres of which
    one is active, an active sphere and a wall).

    Linked-cell search with cells of edge >= 2 R_max + skin.  Returns the int64 keys
    ``i * (ns + nw) + jj``, ascending, with ``jj = j > i`` for spheres and ``ns + w`` for
    walls, and their first indices i (same order).
    """
    pos, radius = spheres.pos, spheres.radius
    ns = pos.shape[0]
    rmax = 0.0
    lo = np.empty(3)
    hi = np.empty(3)
    for d in range(3):
        lo[d] = np.inf
        hi[d] = -np.inf
    for s in range(ns):
        rmax = max(rmax, radius[s])
        for d in range(3):
            lo[d] = min(lo[d], pos[s, d])
            hi[d] = max(hi[d], pos[s, d])
    cell = 2.0 * rmax + skin
    ncell = np.empty(3, np.int64)
    total = 1
    for d in range(3):
        ncell[d] = max(1, min(int(min((hi[d] - lo[d]) / cell, 1e9)), 8 * ns + 64))
        total *= ncell[d]
    # keep memory proportional to the number of spheres in sparse scenes
    while total > 8 * ns + 64:
        for d in range(3):
            ncell[d] = max(1, ncell[d] // 2)
        total = ncell[0] * ncell[1] * ncell[2]
    inv_width = np.empty(3)
    for d in range(3):
        inv_width[d] = 1.0 / max((hi[d] - lo[d]) / ncell[d], 1e-300)
    head = -np.ones(total, np.int64)
    nxt = -np.ones(ns, np.int64)
    cidx = np.empty((ns, 3), np.int64)
    _bin_spheres(pos, lo, inv_width, ncell, head, nxt, cidx)
    raw = np.empty(16 * ns + 16, np.int64)
    raw_first = np.empty(raw.shape[0], np.int64)
    n = -1
    while n < 0:  # keys too short: the scan wrote nothing that counts, redo with room
        n = _scan_cells(spheres, walls, skin, active, ncell, head, nxt, cidx, raw, raw_first)
        if n < 0:
            raw = np.empty(2 * raw.shape[0], np.int64)
            raw_first = np.empty(raw.shape[0], np.int64)
    keys = np.empty(n, np.int64)
    first = np.empty(n, np.int64)
    _sort_pairs(raw[:n], raw_first[:n], np.zeros(ns + 1, np.int64), keys, first)
    return keys, first


# (the search and the sort allocate nothing: compiled without numba's reference counting,
# dem/compiled.py)


@inner_kernel(_nrt=False)
def _bin_spheres(pos, lo, inv_width, ncell, head, nxt, cidx):
    """Linked lists of the spheres in each cell: ``head[cell]`` -> ``nxt[s]`` -> ...;
    ``cidx[s]`` the (3,) cell index of sphere s."""
    for s in range(pos.shape[0]):
        for d in range(3):
            c = int((pos[s, d] - lo[d]) * inv_width[d])
            cidx[s, d] = min(max(c, 0), ncell[d] - 1)
        flat = (cidx[s, 0] * ncell[1] + cidx[s, 1]) * ncell[2] + cidx[s, 2]
        nxt[s] = head[flat]
        head[flat] = s


@inline_kernel()
def _within_skin(pos, radius, s, t, skin):
    """Whether the surfaces of spheres s and t are closer than ``skin`` [m] (the same
    decision from either side: the squares and the sums do not depend on the order)."""
    dx = pos[t, 0] - pos[s, 0]
    dy = pos[t, 1] - pos[s, 1]
    dz = pos[t, 2] - pos[s, 2]
    reach = radius[s] + radius[t] + skin
    return dx * dx + dy * dy + dz * dz < reach * reach


@inline_kernel()
def _add_pair(keys, first, n, i, key):
    """Append ``key`` (first index ``i``) at position n; returns n + 1, or -1 if full."""
    if n == keys.shape[0]:
        return -1
    first[n] = i
    keys[n] = key
    return n + 1


@inline_kernel()
def _add_cell_pairs(spheres, s, t, nxt, own, active, skin, stride, keys, first, n):
    """Append the pairs of sphere s with the spheres of one cell's list (``t`` its head,
    ``nxt`` the links) closer than ``skin`` [m]: of other bodies, and in the cell of s
    (``own``) only those after s; with ``active`` ((ns,) or None), an active sphere only
    after s as well (the pair is found from both sides).  Returns the new count, or -1 if
    full."""
    pos, radius, body = spheres.pos, spheres.radius, spheres.body
    while t >= 0:
        ordered = own if active is None else active[t]
        if (t > s or not ordered) and body[t] != body[s] and _within_skin(pos, radius, s, t, skin):
            i = min(s, t)
            n = _add_pair(keys, first, n, i, i * stride + max(s, t))
            if n < 0:
                return -1
        t = nxt[t]
    return n


@inline_kernel()
def _scan_walls(spheres, walls, skin, active, keys, first, n):
    """Append after the n pairs found the pairs of every sphere (with ``active``, every
    active sphere) with the walls it is closer to than ``skin`` [m]; returns the new
    count, or -1 if full."""
    pos, radius = spheres.pos, spheres.radius
    ns = pos.shape[0]
    stride = ns + walls.point.shape[0]
    for s in range(ns):
        if active is not None and not active[s]:
            continue
        for w in range(walls.point.shape[0]):
            dist = 0.0
            for d in range(3):
                dist += (pos[s, d] - walls.point[w, d]) * walls.normal[w, d]
            if dist < radius[s] + skin:
                n = _add_pair(keys, first, n, s, s * stride + ns + w)
                if n < 0:
                    return -1
    return n


@inner_kernel(_nrt=False)
def _scan_cells(spheres, walls, skin, active, ncell, head, nxt, cidx, keys, first):
    """Write the keys of the pairs closer than the skin into ``keys`` (in no particular
    order) and their first indices into ``first``; return their number, or -1 if the
    arrays are too short.

    ``active`` None: every pair, each visited once, from a half shell: sphere s meets the
    spheres after it in its own cell and all spheres of the 13 neighbour cells whose
    offset is lexicographically positive.  ``active`` ((ns,) uint8): the pairs with an
    active sphere only; each active sphere meets the spheres of its own and all 26
    neighbour cells (a pair of two active spheres is kept from its lower index), and an
    inactive sphere is not looked at, so that the cost grows with the active spheres, not
    with all of them (a chain of dominoes held until touched: the moving ones).
    """
    ns = spheres.pos.shape[0]
    stride = ns + walls.point.shape[0]
    n = 0
    for s in range(ns):
        if active is not None and not active[s]:
            continue
        for ox in range(-1, 2):
            for oy in range(-1, 2):
                for oz in range(-1, 2):
                    if active is None and (ox, oy, oz) < (0, 0, 0):
                        continue  # (the other half of the shell: found from the other cell)
                    cx, cy, cz = cidx[s, 0] + ox, cidx[s, 1] + oy, cidx[s, 2] + oz
                    if min(cx, cy, cz) < 0 or cx >= ncell[0] or cy >= ncell[1] or cz >= ncell[2]:
                        continue
                    own = ox == 0 and oy == 0 and oz == 0
                    t = head[(cx * ncell[1] + cy) * ncell[2] + cz]
                    n = _add_cell_pairs(spheres, s, t, nxt, own, active, skin, stride, keys,
                                        first, n)  # fmt: skip
                    if n < 0:
                        return -1
    return _scan_walls(spheres, walls, skin, active, keys, first, n)


@inner_kernel(_nrt=False)
def _sort_pairs(raw, raw_first, count, keys, first):
    """``raw`` keys (n,) sorted into ``keys`` (n,), their first indices ``raw_first`` into
    ``first``: a counting sort by the first index (``count`` (ns + 1,) zeroed scratch), then
    an insertion sort of the keys of each first index: O(n + ns + sum of g^2) for groups
    of g keys -- a sphere has a handful of listed partners in a packing of similar spheres;
    a sphere with hundreds (one large sphere among small ones) would make np.sort the
    faster choice."""
    n = raw.shape[0]
    for k in range(n):
        count[raw_first[k] + 1] += 1
    for s in range(1, count.shape[0]):
        count[s] += count[s - 1]  # now the beginning of each group
    for k in range(n):
        c = count[raw_first[k]]
        count[raw_first[k]] = c + 1
        first[c] = raw_first[k]
        keys[c] = raw[k]
    # (a key never passes the group boundary: all keys of a group exceed those before it)
    for c in range(1, n):
        key = keys[c]
        k = c
        while k > 0 and keys[k - 1] > key:
            keys[k] = keys[k - 1]
            k -= 1
        keys[k] = key


@njit(cache=True, error_model="numpy")
def build_verlet_list(spheres, walls, bodies, mats, contacts, skin):
    """Rebuild the Verlet list, carrying the history of every existing pair over.

    Returns the number of pairs, or ``-needed`` if the contact arrays are too short (the
    caller grows them and calls again; nothing has been changed then).
    """
    keys, first = _candidate_pairs(spheres, walls, skin)
    n_new = keys.shape[0]
    if n_new > contacts.i.shape[0]:
        return -n_new
    src = np.empty(n_new, np.int64)
    _merge_history(spheres, walls, bodies, mats, contacts, keys, first, src, np.empty(4))
    _list_spheres(spheres, contacts, np.zeros(spheres.pos.shape[0], np.uint8))
    mark_build(bodies)
    return n_new


@inner_kernel(_nrt=False)
def mark_build(bodies):
    """Keep every body's position and orientation at this list build: the reference of
    the displacement test (:func:`needs_rebuild`)."""
    for b in range(bodies.mass.shape[0]):
        for d in range(3):
            bodies.pos_at_build[b, d] = bodies.pos[b, d]
        for d in range(4):
            bodies.quat_at_build[b, d] = bodies.quat[b, d]


@inner_kernel(_nrt=False)
def _merge_history(spheres, walls, bodies, mats, contacts, keys, first, src, props):
    """Write the pairs ``keys`` (sorted; ``first`` their first indices) into ``contacts``,
    in place; a pair that was listed before keeps its whole history, a new one starts
    idle with its properties computed.

    Scratch arrays (allocated by the caller, as this loop runs without numba's reference
    counting): ``src`` (n_new,) int64, ``props`` (4,).

    ``src[c]`` is the old slot of new pair c (-1 for a new pair); it increases with c, as
    both lists are sorted.  The pairs that move to a higher slot (``src[c] < c``) go first,
    from the top: the slot c written is the old slot of no pair still to move (those have
    ``src < c`` or moved already).  Then those that move to a lower slot, from the bottom,
    by the mirrored argument; then the new pairs, whose slots are read by no move.  Slots
    that keep their pair are not touched: one pass over the moved pairs, not a copy of the
    whole list out and back.
    """
    ns = spheres.pos.shape[0]
    stride = ns + walls.point.shape[0]
    n_new = keys.shape[0]
    _old_slots(contacts, keys, ns, stride, src)
    # (a pair moves with its whole row: the dashpot extrapolates vn, an ending contact needs
    # its last overlap (end_impulse); the properties of a listed pair are kept: state.py,
    # MaterialTable)
    for c in range(n_new - 1, -1, -1):
        if 0 <= src[c] < c:
            copy_row(contacts, src[c], contacts, c)
    for c in range(n_new):
        if src[c] > c:
            copy_row(contacts, src[c], contacts, c)
    for c in range(n_new):
        i = first[c]
        jj = keys[c] - i * stride
        j = jj if jj < ns else -(jj - ns) - 1
        contacts.i[c] = i
        contacts.j[c] = j
        if src[c] < 0:
            # (vn and fn are kept as before: set at the onset before they are read; a new
            # pair does not touch: its overlap is not positive, contact_rows)
            contacts.overlap[c] = 0.0
            for d in range(3):
                contacts.shear[c, d] = 0.0
            contacts.fn_viscous[c] = 0.0
            pair_properties(i, j, spheres, walls, bodies, mats, props)
            contacts.kn[c] = props[0]
            contacts.kt[c] = props[1]
            contacts.mu[c] = props[2]
            contacts.cn[c] = props[3]
    contacts.n[0] = n_new


@inline_kernel()
def _old_slots(contacts, keys, ns, stride, src):
    """``src[c]``: the slot of the listed pairs (``contacts``, before the merge) holding the
    pair ``keys[c]``, or -1 if it was not listed.  Both lists are sorted: one merge walk."""
    n_old = max(contacts.n[0], 0)
    o = 0
    old_key = -1
    if n_old > 0:
        old_key = _pair_key(contacts, 0, ns, stride)
    for c in range(keys.shape[0]):
        k = keys[c]
        while o < n_old and old_key < k:
            o += 1  # old pairs now out of range: their contacts have ended already
            if o < n_old:
                old_key = _pair_key(contacts, o, ns, stride)
        src[c] = o if o < n_old and old_key == k else -1


@inline_kernel()
def _pair_key(contacts, c, ns, stride):
    """Sort key ``i * stride + jj`` of listed pair c (``jj = ns + w`` for wall w)."""
    j = contacts.j[c]
    return contacts.i[c] * stride + (j if j >= 0 else ns - j - 1)


@inner_kernel(_nrt=False)
def _list_spheres(spheres, contacts, seen):
    """``spheres.listed``: the spheres of the Verlet list, the only ones whose positions
    the contact kernels read until the next build (the engine updates just these).
    ``seen``: (ns,) zeroed scratch."""
    for c in range(contacts.n[0]):
        seen[contacts.i[c]] = 1
        if contacts.j[c] >= 0:
            seen[contacts.j[c]] = 1
    k = 0
    for s in range(spheres.pos.shape[0]):
        if seen[s]:
            spheres.listed[k] = s
            k += 1
    spheres.n_listed[0] = k


@inline_kernel()
def point_velocity_in_plane(vel, omega, b, rx, rz):
    """:func:`point_velocity` in the xz plane of a planar scene: ``omega = (0, w, 0)``
    and ``r = (rx, 0, rz)`` give ``(v_x + w r_z, v_z - w r_x)`` [m/s]."""
    w = omega[b, 1]
    return vel[b, 0] + w * rz, vel[b, 2] - w * rx


# --------------------------------------------------------------------------- contact law


@inline_kernel()
def apply_at_lever(bodies, b, rx, ry, rz, f0, f1, f2, sign):
    """Add ``sign f`` acting at lever arm ``r`` to the force and torque of body b."""
    bodies.force[b, 0] += sign * f0
    bodies.force[b, 1] += sign * f1
    bodies.force[b, 2] += sign * f2
    bodies.torque[b, 0] += sign * (ry * f2 - rz * f1)
    bodies.torque[b, 1] += sign * (rz * f0 - rx * f2)
    bodies.torque[b, 2] += sign * (rx * f1 - ry * f0)


# --------------------------------------------------------------------------- drivers
# The per-contact bookkeeping of the sphere driver (:func:`_sphere_driver`): the state of
# contact c in ``contacts`` and the forces on the bodies.


@inline_kernel()
def end_contact(bodies, contacts, c, bi, bj, wall, n0, n1, n2, gap, dt, p0, p1, p2):
    """End contact c at the first step without overlap (``gap <= 0``, normal ``n``, contact
    point ``p``).

    Applies the impulse the last kick in contact missed (:func:`end_impulse`) and keeps
    ``overlap = gap`` and ``vn`` = the separation speed of the last drift, from which the
    event time is interpolated.  Returns the tangential elastic energy, which the Coulomb
    limit (-> 0 with the normal force) releases by slip at separation (booked as friction
    dissipation: minus the change of the stored energy).
    """
    last = contacts.overlap[c]
    f_elastic, f_viscous = end_impulse(last, gap, contacts.kn[c], contacts.cn[c], dt)
    contacts.fn[c] = f_elastic + f_viscous
    contacts.fn_viscous[c] = f_viscous
    contacts.vn[c] = (last - gap) / dt
    contacts.overlap[c] = gap
    fn = f_elastic + f_viscous
    if fn != 0.0:
        f0, f1, f2 = fn * n0, fn * n1, fn * n2
        if not wall:
            rx, ry, rz = lever_arm(bodies.pos, bj, p0, p1, p2)
            apply_at_lever(bodies, bj, rx, ry, rz, f0, f1, f2, 1.0)
        rx, ry, rz = lever_arm(bodies.pos, bi, p0, p1, p2)
        apply_at_lever(bodies, bi, rx, ry, rz, f0, f1, f2, -1.0)
    u = contacts.shear
    released = 0.5 * contacts.kt[c] * (u[c, 0] * u[c, 0] + u[c, 1] * u[c, 1] + u[c, 2] * u[c, 2])
    for d in range(3):
        u[c, d] = 0.0
    return released


@inline_kernel()
def idle_pair(contacts, c):
    """Pair c is not in contact this step: its dashpot force (the end impulse of the last
    step, if any) is zero now (stored only if needed: most listed pairs stay idle)."""
    if contacts.fn_viscous[c] != 0.0:
        contacts.fn_viscous[c] = 0.0


@inline_kernel()
def begin_contact(contacts, c):
    """Pair c starts a contact: no shear history (it touches once the driver writes its
    positive overlap)."""
    for d in range(3):
        contacts.shear[c, d] = 0.0


@inline_kernel()
def apply_in_plane(bodies, b, rx, rz, f0, f2, sign):
    """:func:`apply_at_lever` for a force and lever arm in the xz plane: the x and z force
    and the torque about y (a planar scene reads nothing else)."""
    bodies.force[b, 0] += sign * f0
    bodies.force[b, 2] += sign * f2
    bodies.torque[b, 1] += sign * (rz * f0 - rx * f2)


@inline_kernel()
def _yade_shear_velocity(bodies, spheres, contacts, c, i, bi, bj, wall, n0, n1, n2, rsum, overlap):
    """The relative velocity that drives the shear of contact c with YADE's kinematics
    (laws.tangential.yade_shear_velocity): from the velocities of the two sphere centres
    and their spins."""
    pos, body_pos, vel, om = spheres.pos, bodies.pos, bodies.vel, bodies.omega
    Ri = spheres.radius[i]
    ci0, ci1, ci2 = lever_arm(body_pos, bi, pos[i, 0], pos[i, 1], pos[i, 2])
    ci0, ci1, ci2 = point_velocity(vel, om, bi, ci0, ci1, ci2)
    a0, a1, a2 = Ri * om[bi, 0], Ri * om[bi, 1], Ri * om[bi, 2]
    cj0 = cj1 = cj2 = 0.0
    if not wall:
        js = np.uint64(contacts.j[c])
        Rj = spheres.radius[js]
        cj0, cj1, cj2 = lever_arm(body_pos, bj, pos[js, 0], pos[js, 1], pos[js, 2])
        cj0, cj1, cj2 = point_velocity(vel, om, bj, cj0, cj1, cj2)
        a0 += Rj * om[bj, 0]
        a1 += Rj * om[bj, 1]
        a2 += Rj * om[bj, 2]
    return yade_shear_velocity(
        cj0 - ci0, cj1 - ci1, cj2 - ci2, a0, a1, a2, n0, n1, n2, rsum, overlap
    )


@inline_kernel()
def _yade_shear_velocity_in_plane(bodies, spheres, contacts, c, i, bi, bj, wall, n0, n2, rsum,
                                  overlap):  # fmt: skip
    """:func:`_yade_shear_velocity` of a planar scene: in the plane, the sphere centres
    moving with ``(v_x + w r_z, v_z - w r_x)``, ``r`` = centre - centre of mass; returns
    the x and z components."""
    pos, body_pos, vel, om = spheres.pos, bodies.pos, bodies.vel, bodies.omega
    ci0, ci2 = point_velocity_in_plane(
        vel, om, bi, pos[i, 0] - body_pos[bi, 0], pos[i, 2] - body_pos[bi, 2]
    )
    a1 = spheres.radius[i] * om[bi, 1]
    cj0 = cj2 = 0.0
    if not wall:
        js = np.uint64(contacts.j[c])
        cj0, cj2 = point_velocity_in_plane(
            vel, om, bj, pos[js, 0] - body_pos[bj, 0], pos[js, 2] - body_pos[bj, 2]
        )
        a1 += spheres.radius[js] * om[bj, 1]
    s0, _, s2 = yade_shear_velocity(
        cj0 - ci0, 0.0, cj2 - ci2, 0.0, a1, 0.0, n0, 0.0, n2, rsum, overlap
    )
    return s0, s2


def _sphere_driver(PLANAR):  # (capital: a constant of the compiled kernels)
    """The sphere driver's kernel ``compute_forces`` for a scene of the kind ``PLANAR``.

    One source for both kinds of scene, compiled once for each (as engine.time_loop):
    the planar kernels (a planar scene, planar.py) pass the components that are zero in
    the plane as 0.0 to the same per-pair geometry and law, drop them from the results
    and compute the relative velocities in the plane -- the same in-plane numbers with a
    third fewer loads and operations.  numba prunes the branches of the other kind before
    it types the calls of the per-pair functions, so each kernel compiles and inlines its
    own arithmetic only (the flag is tested by name in every ``if``: numba does not
    follow a constant through a variable or a ``not``).  Passed as an argument instead,
    even a literal one (``numba.literally``), the flag is resolved only after typing:
    both kinds' calls are typed, for each value and for the first, non-literal attempt."""

    @njit(cache=True, error_model="numpy", _nrt=False)
    def compute_forces(
        bodies, spheres, walls, contacts, dt, ledger, changes, change_lag, first_step,
        shear_kinematics,
    ):  # fmt: skip
        """Contact forces and torques on all bodies for the current positions.

        ``ledger[LEDGER_FRICTION]`` -= change of the energy stored in the tangential springs
        (the work of the tangential and dashpot forces is booked after the kick, from
        contact_rows.rows_power with the full-step velocities).  A pair in contact, or
        whose contact ends, gets the point and normal of its row.  Every contact that
        starts or ends is listed in ``changes`` (K, 3) and ``change_lag`` (K,)
        (contact_rows.log_change: its bodies, ONSET or END, the time since); returns their
        count.
        ``first_step``: the initial configuration, no shear increment (no previous step).
        ``shear_kinematics``: SHEAR_CONTACT_POINT or SHEAR_YADE (laws/tangential.py).
        """
        bodies.force[:, :] = 0.0
        bodies.torque[:, :] = 0.0
        pos = spheres.pos
        body_pos, vel, om = bodies.pos, bodies.vel, bodies.omega
        u = contacts.shear
        n_changes = 0
        for c in range(contacts.n[0]):
            # (unsigned indices: numba adds no negative-index wraparound to every access)
            i = np.uint64(contacts.i[c])
            j = contacts.j[c]
            bi = np.uint64(spheres.body[i])
            Ri = spheres.radius[i]
            touching = contacts.overlap[c] > 0.0  # (it touched at the last step)
            wall = j < 0
            yi = 0.0 if PLANAR else pos[i, 1]
            if not wall:
                j = np.uint64(j)
                bj = np.uint64(spheres.body[j])
                partner = np.int64(bj)  # (the body in the list of changes)
                rsum = Ri + spheres.radius[j]
                yj = 0.0 if PLANAR else pos[j, 1]
                near, n0, n1, n2, overlap = sphere_sphere(
                    pos[i, 0], yi, pos[i, 2], pos[j, 0], yj, pos[j, 2], rsum, touching
                )
            else:
                bj = bi  # (unused)
                partner = j  # (the wall, -(w + 1))
                w = np.uint64(-j - 1)
                wp, wn = walls.point, walls.normal
                wy = 0.0 if PLANAR else wp[w, 1]
                nwy = 0.0 if PLANAR else wn[w, 1]
                near, n0, n1, n2, overlap = sphere_wall(
                    pos[i, 0], yi, pos[i, 2], Ri, wp[w, 0], wy, wp[w, 2], wn[w, 0], nwy, wn[w, 2],
                    touching,
                )  # fmt: skip
                rsum = 2.0 * Ri  # (SHEAR_YADE: a wall takes the sphere's radius)
            if PLANAR:
                n1 = 0.0  # (not -0.0: the sign of the zero the wall's normal gives)
            if not near:
                idle_pair(contacts, c)
                continue
            if overlap <= 0.0 and not touching:  # (d2 < rsum^2, but |d| rounds to rsum)
                idle_pair(contacts, c)
                continue
            p0, p1, p2 = contact_point(pos[i, 0], yi, pos[i, 2], Ri, n0, n1, n2, overlap)
            if PLANAR:
                p1 = pos[i, 1]  # (the plane's y: it enters only the torque's x and z)
            contacts.point[c, 0], contacts.point[c, 1], contacts.point[c, 2] = p0, p1, p2
            contacts.normal[c, 0], contacts.normal[c, 1], contacts.normal[c, 2] = n0, n1, n2
            if overlap <= 0.0:  # a contact opened in the last drift
                ledger[LEDGER_FRICTION] += end_contact(
                    bodies, contacts, c, bi, bj, wall, n0, n1, n2, overlap, dt, p0, p1, p2
                )  # (which keeps the separation speed of the last drift in vn)
                lag = event_lag(overlap, abs(contacts.vn[c]), dt, first_step)
                n_changes = log_change(changes, change_lag, n_changes, bi, partner, END, lag)
                continue
            new_contact = not touching
            if new_contact:
                begin_contact(contacts, c)
            # relative velocity of the contact point, j minus i (a wall is fixed), and the
            # spin of the pair about the normal
            ri0, ri1, ri2 = lever_arm(body_pos, bi, p0, p1, p2)
            rj0 = rj1 = rj2 = 0.0
            if PLANAR:
                vi0, vi2 = point_velocity_in_plane(vel, om, bi, ri0, ri2)
                dv0, dv1, dv2 = -vi0, 0.0, -vi2
                if not wall:
                    rj0, rj2 = p0 - body_pos[bj, 0], p2 - body_pos[bj, 2]
                    vj0, vj2 = point_velocity_in_plane(vel, om, bj, rj0, rj2)
                    dv0 += vj0
                    dv2 += vj2
                spin = 0.0
            else:
                vi0, vi1, vi2 = point_velocity(vel, om, bi, ri0, ri1, ri2)
                if not wall:
                    rj0, rj1, rj2 = lever_arm(body_pos, bj, p0, p1, p2)
                    vj0, vj1, vj2 = point_velocity(vel, om, bj, rj0, rj1, rj2)
                    spin = 0.5 * n0 * (om[bi, 0] + om[bj, 0])
                    spin += 0.5 * n1 * (om[bi, 1] + om[bj, 1])
                    spin += 0.5 * n2 * (om[bi, 2] + om[bj, 2])
                else:
                    vj0 = vj1 = vj2 = 0.0
                    spin = 0.5 * n0 * om[bi, 0]
                    spin += 0.5 * n1 * om[bi, 1]
                    spin += 0.5 * n2 * om[bi, 2]
                dv0, dv1, dv2 = vj0 - vi0, vj1 - vi1, vj2 - vi2
            # the relative velocity that drives the shear (laws/tangential.py)
            s0, s1, s2 = dv0, dv1, dv2
            if shear_kinematics == SHEAR_YADE:
                if PLANAR:
                    s0, s2 = _yade_shear_velocity_in_plane(
                        bodies, spheres, contacts, c, i, bi, bj, wall, n0, n2, rsum, overlap
                    )
                else:
                    s0, s1, s2 = _yade_shear_velocity(
                        bodies, spheres, contacts, c, i, bi, bj, wall, n0, n1, n2, rsum, overlap
                    )
            # the contact point's law (a new contact: no shear history, begin_contact); no
            # turn of the shear about a planar contact's normal (a constant: the planar
            # kernel compiles no turn)
            turn = 0.0 if PLANAR else spin * dt
            fn, fn_viscous, vn, u0, u1, u2, released, f0, f1, f2 = point_law(
                overlap, n0, n1, n2, dv0, dv1, dv2, s0, s1, s2, turn, u[c, 0],
                0.0 if PLANAR else u[c, 1], u[c, 2], contacts.vn[c], new_contact, contacts.kn[c],
                contacts.kt[c], contacts.mu[c], contacts.cn[c], dt, first_step, False,
            )  # fmt: skip
            u[c, 0], u[c, 1], u[c, 2] = u0, 0.0 if PLANAR else u1, u2
            contacts.vn[c] = vn
            contacts.overlap[c] = overlap
            contacts.fn[c] = fn
            contacts.fn_viscous[c] = fn_viscous
            if new_contact:  # (approached at -vn over the last drift)
                lag = event_lag(overlap, -vn, dt, first_step)
                n_changes = log_change(changes, change_lag, n_changes, bi, partner, ONSET, lag)
            # friction ledger, part 1: minus the change of the energy stored in the spring
            ledger[LEDGER_FRICTION] += released
            if PLANAR:
                if not wall:
                    apply_in_plane(bodies, bj, rj0, rj2, f0, f2, 1.0)
                apply_in_plane(bodies, bi, ri0, ri2, f0, f2, -1.0)
            else:
                if not wall:
                    apply_at_lever(bodies, bj, rj0, rj1, rj2, f0, f1, f2, 1.0)
                apply_at_lever(bodies, bi, ri0, ri1, ri2, f0, f1, f2, -1.0)
        return n_changes

    return compute_forces


compute_forces = _sphere_driver(False)
compute_forces_planar = _sphere_driver(True)

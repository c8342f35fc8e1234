"""Contacts of rounded cuboids with spheres: the per-pair driver (a box and a ball, a box
and the spheres of a clump).

Each step :func:`box_sphere_forces` visits every (box, sphere) pair of different bodies
within reach and applies to its contact point (``shapes.cuboid.box_sphere``, or
``shapes.rectangle.rect_sphere`` in a planar scene: the centre of the sphere against the
core box, overlap ``r_box + R - distance``; face, edge or vertex region implicit) the law
of the box-box points, through the same code (boxes._point_row, laws.point.point_law):
linear normal force ``k_n delta - c_n v_n`` with the onset average of the overlap and
the end impulse (laws.linear.onset_averaged_overlap, laws.linear.end_impulse); Cundall-Strack
friction with one shear history per pair; the dashpot from the pair's restitution and
the effective mass at the contact point (boxes.inverse_mass_at); stiffness, friction and
restitution of the material pair (material_pairs.material_pair: the rounding and the sphere's
radius).  Energies, power, peak forces and the contact-force recorder are those of every
contact table (contact_rows.py, through boxes.box_energies, box_power, box_peak_force and
box_contact_forces), with multiplicity 1.
A sphere touches a convex box at one point, so the pair is its own key, and a planar row
stands for one point (no doubling along y).  Hertz scenes hold no spheres
(``Scene.build`` refuses them), so the law here is the linear one.

Rows live in ``Boxes.sphere_rows`` (the layout of the box rows, ``j`` the sphere id), in
pair order (box, then sphere).  Onsets and ends of a pair enter ``Boxes.changes`` after
those of box_forces, so the engine books them as the box pairs' (events, pair
statistics, release of held bodies).  Pairs within reach are found in two stages, as for
the box pairs: a neighbour list of candidates (:func:`build_box_sphere_candidates`, built
with the spheres' Verlet list), and each step the bounding test on the candidates: the
sphere's centre closer to the box's centre than the box's reach plus ``R`` plus the
margin (half the smaller of ``R`` and the box's smallest outer half-extent, so that a
point is seen opening: its end impulse).  The sphere's centre is computed from its owner
body (``Spheres.pos`` is kept only for spheres in the Verlet list).
"""

from __future__ import annotations

import numpy as np

from dominowave.dem.boxes import (
    _copy_rows,
    _end,
    _log_bodies,
    _open_row,
    _point_row,
    _reach_of,
    _release,
)
from dominowave.dem.compiled import inline_kernel, inner_kernel
from dominowave.dem.contact import _candidate_pairs
from dominowave.dem.contact_rows import END, ONSET, event_lag
from dominowave.dem.material_pairs import material_pair
from dominowave.dem.shapes.cuboid import box_sphere
from dominowave.dem.shapes.rectangle import rect_sphere
from dominowave.dem.state import Spheres

__all__ = [
    "box_sphere_forces",
    "box_sphere_forces_general",
    "box_sphere_forces_planar",
    "build_box_sphere_candidates",
]


@inline_kernel()
def _sphere_centre(bodies, spheres, s, out):
    """World centre ``x_b + R_b u_s`` [m] of sphere s into ``out`` (3,)."""
    b = spheres.body[s]
    u = spheres.local[s]
    for d in range(3):
        out[d] = (
            bodies.pos[b, d]
            + bodies.rot[b, d, 0] * u[0]
            + bodies.rot[b, d, 1] * u[1]
            + bodies.rot[b, d, 2] * u[2]
        )


@inline_kernel()
def _margin(boxes, spheres, a, s):
    """Margin [m] of the pair's contact point: half the smaller of the sphere's radius and
    the box's smallest outer half-extent (a point moves far less in one step)."""
    h = boxes.half[a]
    size = min(h[0], h[1], h[2]) + boxes.radius[a]
    return 0.5 * min(size, spheres.radius[s])


@inner_kernel(_nrt=False)
def _drop(old, boxes, spheres, bodies, o, code, ns, ledger):
    """Old rows from o on of pairs before ``code`` are out of reach: release their shear
    springs, log their ends; returns the first row of ``code`` or after."""
    while o < old.n[0] and old.i[o] * ns + old.j[o] < code:
        _release(old, o, ledger)
        _log_bodies(boxes, boxes.body[old.i[o]], spheres.body[old.j[o]], END, 0.0)
        o += 1
    return o


def _box_sphere_driver(PLANAR):  # (capital: a constant of the compiled kernel)
    """``box_sphere_forces`` of a scene of the kind ``PLANAR``: the planar geometry
    (shapes.rectangle.rect_sphere) or the 3D one (shapes.cuboid.box_sphere), so that a
    scene compiles only its own (one source, as boxes._box_driver)."""

    @inner_kernel(_nrt=False)
    def forces(bodies, spheres, boxes, mats, dt, ledger, first_step):
        """Add the forces and torques of every box-sphere contact to the bodies (after
        box_forces; the pairs of :func:`build_box_sphere_candidates`' list, or all pairs
        without one: the same pairs pass, in the same order), rebuild
        ``boxes.sphere_rows``, book the change of the energy stored in their shear springs
        in ``ledger[LEDGER_FRICTION]``, append the body pairs whose contact started or
        ended to ``boxes.changes``."""
        old, new = boxes.sphere_rows, boxes.sphere_next
        nx = boxes.body.shape[0]
        ns = spheres.body.shape[0]
        if ns == 0:  # (a scene of boxes only: nothing to do, every step)
            return
        props = boxes.props
        c_s = boxes.work[0, 0, :3]  # (scratch: the sphere's centre)
        o = 0
        n_new = 0
        for a in range(nx):
            listed = boxes.n_sphere_cand[0] >= 0
            lo, hi = (
                (boxes.sphere_cand_start[a], boxes.sphere_cand_start[a + 1]) if listed else (0, ns)
            )
            if lo == hi:  # (most boxes: no sphere near)
                continue
            ba = boxes.body[a]
            xa, Ra, ha, ra = bodies.pos[ba], bodies.rot[ba], boxes.half[a], boxes.radius[a]
            reach = _reach_of(boxes, a)
            for k in range(lo, hi):
                s = boxes.sphere_cand[k] - a * ns if listed else k
                bs = spheres.body[s]
                if bs == ba or (bodies.held[ba] == 1 and bodies.held[bs] == 1):
                    continue
                _sphere_centre(bodies, spheres, s, c_s)
                radius = spheres.radius[s]
                margin = _margin(boxes, spheres, a, s)
                d2 = 0.0
                for d in range(3):
                    d2 += (c_s[d] - xa[d]) ** 2
                if d2 >= (reach + radius + margin) ** 2:
                    continue
                code = a * ns + s
                o = _drop(old, boxes, spheres, bodies, o, code, ns, ledger)
                q = o if o < old.n[0] and old.i[o] * ns + old.j[o] == code else -1
                if q >= 0:
                    o += 1
                if PLANAR:
                    m = rect_sphere(xa, Ra, ha, ra, c_s, radius, margin, boxes.m_normal,
                                    boxes.m_point, boxes.m_overlap, boxes.m_key)  # fmt: skip
                else:
                    m = box_sphere(xa, Ra, ha, ra, c_s, radius, margin, boxes.m_normal,
                                   boxes.m_point, boxes.m_overlap, boxes.m_key)  # fmt: skip
                overlap = boxes.m_overlap[0] if m > 0 else -margin
                if overlap <= 0.0:
                    if q >= 0:
                        if m > 0:
                            _end(bodies, old, q, overlap, dt, ba, bs, False, ledger, False)
                        else:
                            _release(old, q, ledger)
                        speed = (old.overlap[q] - overlap) / dt
                        _log_bodies(boxes, ba, bs, END, event_lag(overlap, speed, dt, first_step))
                    continue
                c = n_new
                n_new += 1
                _open_row(new, c, a, s, 0, 1.0, boxes.m_normal[0], boxes.m_point[0])
                fresh = q < 0
                if fresh:
                    material_pair(mats, boxes.material[a], ra, spheres.material[s], radius, props)
                _point_row(bodies, old, new, c, q, props, ba, bs, False, overlap, dt, first_step,
                           False, ledger)  # fmt: skip
                if fresh:
                    _log_bodies(
                        boxes, ba, bs, ONSET, event_lag(overlap, -new.vn[c], dt, first_step)
                    )
        _drop(old, boxes, spheres, bodies, o, 2**62, ns, ledger)
        _copy_rows(new, old, n_new)

    return forces


box_sphere_forces_planar = _box_sphere_driver(True)
box_sphere_forces_general = _box_sphere_driver(False)


@inner_kernel(_nrt=False)
def box_sphere_forces(bodies, spheres, boxes, mats, dt, ledger, first_step, planar):
    """:func:`box_sphere_forces_planar` or :func:`box_sphere_forces_general` by ``planar``
    (the time loop calls its kind's; this is for the benchmarks)."""
    if planar:
        box_sphere_forces_planar(bodies, spheres, boxes, mats, dt, ledger, first_step)
    else:
        box_sphere_forces_general(bodies, spheres, boxes, mats, dt, ledger, first_step)


# (allocates: compiled with numba's reference counting, as boxes.build_box_candidates)
@inner_kernel(_nrt=True)
def build_box_sphere_candidates(bodies, spheres, boxes, walls, skin):
    """The neighbour list of the box-sphere contacts: every (box, sphere) pair of
    different bodies whose bounding spheres come closer than ``skin`` [m], into
    ``boxes.sphere_cand`` (codes ``box * n_spheres + sphere``, ascending) and
    ``boxes.sphere_cand_start`` (first candidate of each box).  Returns their number, or
    ``-needed`` if ``boxes.sphere_cand`` is too short (then ``n_sphere_cand`` is -1:
    every pair is a candidate until the caller grows it and builds again).

    Bounding spheres: the box's core half-diagonal plus its rounding (the reach of
    :func:`box_sphere_forces`' test), the sphere's radius plus the largest margin,
    ``1.5 R``; so a pair passes that test only if their bounding spheres overlap, and
    with every core point and sphere centre moving at most skin/2 between builds
    (engine.py rebuilds both lists with the spheres' Verlet list) no pair outside the
    list can.  The search is the linked-cell search of the spheres (contact.py) over
    both kinds of bounding sphere."""
    nx = boxes.body.shape[0]
    ns = spheres.body.shape[0]
    if ns == 0:  # (a scene of boxes only: an empty list)
        boxes.sphere_cand_start[:] = 0
        boxes.n_sphere_cand[0] = 0
        return 0
    nt = nx + ns
    pos = np.empty((nt, 3))
    radius = np.empty(nt)
    body = np.empty(nt, np.int64)
    centre = np.empty(3)
    for x in range(nx):
        for d in range(3):
            pos[x, d] = bodies.pos[boxes.body[x], d]
        radius[x] = _reach_of(boxes, x)
        body[x] = boxes.body[x]
    for s in range(ns):
        _sphere_centre(bodies, spheres, s, centre)
        for d in range(3):
            pos[nx + s, d] = centre[d]
        radius[nx + s] = 1.5 * spheres.radius[s]
        body[nx + s] = spheres.body[s]
    listed = np.arange(nt)
    bound = Spheres(
        body=body,
        radius=radius,
        local=pos,
        material=np.zeros(nt, np.int64),
        pos=pos,
        listed=listed,
        n_listed=np.full(1, nt, np.int64),
    )
    keys, _ = _candidate_pairs(bound, walls, skin)
    stride = nt + walls.point.shape[0]
    n = 0
    for k in range(keys.shape[0]):
        i, jj = keys[k] // stride, keys[k] % stride
        if i < nx and nx <= jj < nt:
            n += 1
    if n > boxes.sphere_cand.shape[0]:
        boxes.n_sphere_cand[0] = -1
        return -n
    start = boxes.sphere_cand_start
    start[:] = 0
    n = 0
    for k in range(keys.shape[0]):
        i, jj = keys[k] // stride, keys[k] % stride
        if i < nx and nx <= jj < nt:
            boxes.sphere_cand[n] = i * ns + (jj - nx)
            start[i + 1] += 1
            n += 1
    for x in range(nx):
        start[x + 1] += start[x]
    boxes.n_sphere_cand[0] = n
    return n

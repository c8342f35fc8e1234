"""Contacts of rounded cuboids with spheres: the per-pair driver (a box and a ball, a box
and the spheres of a clump).

Each step :func:`box_sphere_forces` visits every (box, sphere) pair of different bodies
within reach and applies to its contact point (``shapes.cuboid.box_sphere``, or
``shapes.rectangle.rect_sphere`` in a planar scene: the centre of the sphere against the
core box, overlap ``r_box + R - distance``; face, edge or vertex region implicit) the law
of the box-box points (boxes.py): linear normal force ``k_n delta - c_n v_n`` with the
onset average of the overlap and the end impulse (contact.onset_averaged_overlap,
contact.end_impulse); Cundall-Strack friction with one shear history per pair; the
dashpot from the pair's restitution and the effective mass at the contact point
(boxes.inverse_mass_at); stiffness, friction and restitution of the material pair
(contact.particle_stiffness with the rounding and the sphere's radius, contact.pair_*).
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
from numba import njit

from dominowave.dem.boxes import (
    _apply,
    _copy_rows,
    _end,
    _lag,
    _reach_of,
    _relative_velocity,
    _release,
    inverse_mass_at,
)
from dominowave.dem.contact import (
    END,
    ONSET,
    _candidate_pairs,
    cundall_strack,
    onset_averaged_overlap,
    pair_friction_restitution,
    pair_stiffness,
    particle_stiffness,
    rotate_shear,
    viscous_coefficient,
)
from dominowave.dem.energy import LEDGER_FRICTION, POWER_FRICTION, POWER_VISCOUS
from dominowave.dem.shapes.cuboid import box_sphere
from dominowave.dem.shapes.rectangle import rect_sphere
from dominowave.dem.state import Spheres

__all__ = [
    "box_sphere_contact_forces",
    "box_sphere_energies",
    "box_sphere_forces",
    "box_sphere_power",
    "build_box_sphere_candidates",
]


@njit(cache=True, error_model="numpy", inline="always")
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


@njit(cache=True, error_model="numpy", inline="always")
def _margin(boxes, spheres, a, s):
    """Margin [m] of the pair's contact point: half the smaller of the sphere's radius and
    the box's smallest outer half-extent (a point moves far less in one step)."""
    h = boxes.half[a]
    size = min(h[0], h[1], h[2]) + boxes.radius[a]
    return 0.5 * min(size, spheres.radius[s])


@njit(cache=True, error_model="numpy", inline="always")
def _log_pair(boxes, ba, bs, kind, lag):
    """Record that the contact of box body ``ba`` with sphere body ``bs`` started (ONSET)
    or ended (END) ``lag`` [s] before this step (boxes.changes, after box_forces')."""
    k = boxes.n_changes[0]
    if k == boxes.changes.shape[0]:
        raise RuntimeError("box contact changes full")
    boxes.changes[k, 0] = ba
    boxes.changes[k, 1] = bs
    boxes.changes[k, 2] = kind
    boxes.change_lag[k] = lag
    boxes.n_changes[0] = k + 1


@njit(cache=True, error_model="numpy", _nrt=False)
def _properties(boxes, spheres, mats, a, s, out):
    """kn, kt, mu, restitution of the contact of box a with sphere s into ``out[0:4]``."""
    rule = mats.rule[0]
    ma, ms = boxes.material[a], spheres.material[s]
    ka = particle_stiffness(mats.stiffness[ma], boxes.radius[a], rule)
    ks = particle_stiffness(mats.stiffness[ms], spheres.radius[s], rule)
    out[0] = pair_stiffness(ka, ks, rule)
    out[1] = pair_stiffness(ka * mats.kt_ratio[ma], ks * mats.kt_ratio[ms], rule)
    out[2], out[3] = pair_friction_restitution(mats, ma, ms)


@njit(cache=True, error_model="numpy", _nrt=False)
def _drop(old, boxes, spheres, bodies, o, code, ns, ledger):
    """Old rows from o on of pairs before ``code`` are out of reach: release their shear
    springs, log their ends; returns the first row of ``code`` or after."""
    while o < old.n[0] and old.i[o] * ns + old.j[o] < code:
        _release(old, o, ledger)
        _log_pair(boxes, boxes.body[old.i[o]], spheres.body[old.j[o]], END, 0.0)
        o += 1
    return o


@njit(cache=True, error_model="numpy", _nrt=False)
def box_sphere_forces(bodies, spheres, boxes, mats, dt, ledger, first_step, planar):
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
    capacity = new.i.shape[0]
    props = boxes.props
    c_s = boxes.work[0, 0, :3]  # (scratch: the sphere's centre)
    o = 0
    n_new = 0
    for a in range(nx):
        listed = boxes.n_sphere_cand[0] >= 0
        lo, hi = (boxes.sphere_cand_start[a], boxes.sphere_cand_start[a + 1]) if listed else (0, ns)
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
            if planar:
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
                    _log_pair(boxes, ba, bs, END, _lag(overlap, speed, dt, first_step))
                continue
            if n_new == capacity:
                raise RuntimeError("box-sphere contact rows full")
            c = n_new
            n_new += 1
            n0, n1, n2 = boxes.m_normal[0, 0], boxes.m_normal[0, 1], boxes.m_normal[0, 2]
            new.i[c] = a
            new.j[c] = s
            new.key[c] = 0
            new.mult[c] = 1.0
            for d in range(3):
                new.normal[c, d] = boxes.m_normal[0, d]
                new.point[c, d] = boxes.m_point[0, d]
            p = new.point[c]
            fresh = q < 0
            if fresh:
                _properties(boxes, spheres, mats, a, s, props)
                new.kn[c], new.kt[c], new.mu[c] = props[0], props[1], props[2]
                inv = inverse_mass_at(
                    bodies, ba, p[0] - xa[0], p[1] - xa[1], p[2] - xa[2], n0, n1, n2
                ) + inverse_mass_at(
                    bodies, bs, p[0] - bodies.pos[bs, 0], p[1] - bodies.pos[bs, 1],
                    p[2] - bodies.pos[bs, 2], n0, n1, n2,
                )  # fmt: skip
                new.cn[c] = viscous_coefficient(props[3], 1.0 / inv, new.kn[c])
                u0 = u1 = u2 = 0.0
                vn_old = 0.0
            else:
                new.kn[c], new.kt[c], new.mu[c], new.cn[c] = (
                    old.kn[q], old.kt[q], old.mu[q], old.cn[q],
                )  # fmt: skip
                u0, u1, u2 = old.shear[q, 0], old.shear[q, 1], old.shear[q, 2]
                vn_old = old.vn[q]
            stored = u0 * u0 + u1 * u1 + u2 * u2
            dv0, dv1, dv2 = _relative_velocity(bodies, bodies.vel, bodies.omega, ba, bs, False, p)
            vn = dv0 * n0 + dv1 * n1 + dv2 * n2
            om = bodies.omega
            spin = n0 * (om[ba, 0] + om[bs, 0]) + n1 * (om[ba, 1] + om[bs, 1])
            spin += n2 * (om[ba, 2] + om[bs, 2])
            u0, u1, u2 = rotate_shear(u0, u1, u2, n0, n1, n2, 0.5 * spin * dt)
            increment = 0.0 if first_step else dt
            u0 += (dv0 - vn * n0) * increment
            u1 += (dv1 - vn * n1) * increment
            u2 += (dv2 - vn * n2) * increment
            kt = new.kt[c]
            vn_dashpot = vn if fresh else 1.5 * vn - 0.5 * vn_old
            weight, overlap_kick = onset_averaged_overlap(overlap, vn, dt, fresh)
            fn_elastic = new.kn[c] * overlap_kick
            fn_viscous = -new.cn[c] * vn_dashpot * weight
            u0, u1, u2 = cundall_strack(u0, u1, u2, kt, new.mu[c], fn_elastic)
            new.shear[c, 0], new.shear[c, 1], new.shear[c, 2] = u0, u1, u2
            stored -= u0 * u0 + u1 * u1 + u2 * u2
            ledger[LEDGER_FRICTION] += 0.5 * kt * stored
            fn = fn_elastic + fn_viscous
            new.overlap[c] = overlap
            new.vn[c] = vn
            new.fn[c] = fn
            new.fn_viscous[c] = fn_viscous
            f0 = fn * n0 - kt * u0
            f1 = fn * n1 - kt * u1
            f2 = fn * n2 - kt * u2
            _apply(bodies, bs, p, f0, f1, f2, 1.0)
            _apply(bodies, ba, p, f0, f1, f2, -1.0)
            if fresh:
                _log_pair(boxes, ba, bs, ONSET, _lag(overlap, -vn, dt, first_step))
    _drop(old, boxes, spheres, bodies, o, 2**62, ns, ledger)
    _copy_rows(new, old, n_new)


@njit(cache=True, error_model="numpy", _nrt=False)
def box_sphere_power(bodies, spheres, boxes, out):
    """Add the power [W] of the box-sphere dashpots (``out[POWER_VISCOUS]``) and
    tangential forces (``out[POWER_FRICTION]``) at the full-step velocities."""
    rows = boxes.sphere_rows
    for c in range(rows.n[0]):
        bi = boxes.body[rows.i[c]]
        bj = spheres.body[rows.j[c]]
        dv0, dv1, dv2 = _relative_velocity(
            bodies, bodies.vel_full, bodies.omega_full, bi, bj, False, rows.point[c]
        )
        n = rows.normal[c]
        u = rows.shear[c]
        out[POWER_VISCOUS] += rows.fn_viscous[c] * (n[0] * dv0 + n[1] * dv1 + n[2] * dv2)
        out[POWER_FRICTION] -= rows.kt[c] * (u[0] * dv0 + u[1] * dv1 + u[2] * dv2)


@njit(cache=True, error_model="numpy", _nrt=False)
def box_sphere_energies(boxes, out):
    """Add the elastic energies [J] of the box-sphere contacts to ``out`` (ENERGY_NAMES
    vector: ``k_n delta^2 / 2`` to entry 3, ``k_t |u|^2 / 2`` to 4, both to 8)."""
    rows = boxes.sphere_rows
    en = 0.0
    es = 0.0
    for c in range(rows.n[0]):
        u = rows.shear[c]
        en += 0.5 * rows.kn[c] * rows.overlap[c] ** 2
        es += 0.5 * rows.kt[c] * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    out[3] += en
    out[4] += es
    out[8] += en + es


@njit(cache=True, error_model="numpy", _nrt=False)
def box_sphere_contact_forces(boxes, n_spheres, first, second, point, force):
    """The box-sphere rows for the contact-force recorder (boxes.box_contact_forces'
    layout): ``first`` the box's shape id ``n_spheres + box``, ``second`` the sphere,
    ``force`` [N] the force on the sphere, ``point`` [m]; returns the number of rows."""
    rows = boxes.sphere_rows
    for c in range(rows.n[0]):
        n = rows.normal[c]
        u = rows.shear[c]
        first[c] = n_spheres + rows.i[c]
        second[c] = rows.j[c]
        for d in range(3):
            point[c, d] = rows.point[c, d]
            force[c, d] = rows.fn[c] * n[d] - rows.kt[c] * u[d]
    return rows.n[0]


# (allocates: compiled with numba's reference counting, as boxes.build_box_candidates)
@njit(cache=True, error_model="numpy", _nrt=True)
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

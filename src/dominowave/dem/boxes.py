"""Rounded-cuboid bodies in the engine: their state and the contact driver of their
points with boxes, walls and spheres, in one table.

A box body is a rigid body of ``Bodies`` (mass, inertia, quaternion, the same integrator
as a clump) whose shape is a rounded cuboid (``shapes.cuboid``): core half-extents ``h``
in its principal frame and rounding radius ``r``.  Each step :func:`box_forces` finds the
contact manifold of every box-box and box-wall pair within reach (``shapes.cuboid`` in 3D,
``shapes.rectangle`` in a planar scene, each of whose points stands for the two ends of a
cuboid edge along y, or one point of a core without extent along y:
shapes.rectangle.multiplicity), then the one point of every box-sphere pair
(:func:`_box_sphere_pass`), and applies to every point the one law of every contact
point (laws/point.py: the linear or Hertz normal force, Cundall-Strack friction, the
dashpot fixed at the point's onset from the two bodies' effective mass at the point,
:func:`inverse_mass_at`), with the constants of the pair's materials and the rounding
radius as the sphere radius (material_pairs.material_pair).  A point carries its shear
history from step to step by its feature key: a touching point with a new key continues
the nearest unmatched old point of its pair, so that a contact keeps its history when its
touching feature pair changes.

Contact rows are kept in pair order (box i, then partner: boxes j > i, then walls; then
the box-sphere rows, box then sphere, partner ``j = nx + s``) in one table and rebuilt
every step.  Pairs within reach are found in two stages, as for spheres: a
neighbour (Verlet) list of candidate pairs whose bounding spheres come closer than the
skin (:func:`build_box_candidates`, the linked-cell search of contact.py, rebuilt with the
spheres' list when a body may have moved by half the skin, and after the release of a
held box whose pairs it left out), and each step the bounding tests of
:func:`box_forces` on the candidates only.  The candidates are a superset of the
pairs that pass those tests, visited in the same order, so the forces do not depend on
when the list was built.  Held boxes (engine.py) have no rows with other held boxes,
nor with the walls until a moving box is among their candidates (:func:`_held_pair`);
the loop of each step looks only at the candidates of the boxes that are not held and
at the wall pairs of the held boxes next to them (:func:`_visit_pairs`), so a chain of
held dominoes costs what its moving part costs.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from dominowave.dem.compiled import inline_kernel, inner_kernel
from dominowave.dem.contact import _candidate_pairs, _scan_walls, apply_at_lever
from dominowave.dem.contact_rows import (
    END,
    ONSET,
    copy_row,
    event_lag,
    log_change,
    relative_velocity,
    rows_contact_forces,
    rows_elastic_energy,
    rows_peak_force,
    rows_power,
)
from dominowave.dem.energy import (
    E_ELASTIC_NORMAL,
    E_ELASTIC_TANGENTIAL,
    E_TOTAL,
    LEDGER_FRICTION,
)
from dominowave.dem.integrate import ROT_AXIS, ROT_FREE, ROT_ISOTROPIC
from dominowave.dem.laws.hertz import (
    LAW_HERTZ,
    LAW_LINEAR,
    hertz_coefficient,
    hertz_modulus,
)
from dominowave.dem.laws.linear import end_impulse
from dominowave.dem.laws.point import onset_dashpot, point_law
from dominowave.dem.material_pairs import material_pair
from dominowave.dem.shapes.cuboid import MAX_POINTS, box_box, box_plane, box_sphere, faces_separate
from dominowave.dem.shapes.rectangle import (
    edges_separate,
    multiplicity,
    rect_plane,
    rect_rect,
    rect_sphere,
)
from dominowave.dem.state import Spheres, empty_contacts

__all__ = [
    "Boxes",
    "box_contact_forces",
    "box_energies",
    "box_forces",
    "box_forces_general",
    "box_forces_general_spheres",
    "box_forces_planar",
    "box_forces_planar_spheres",
    "box_peak_force",
    "box_power",
    "box_state",
    "boxes_from_state",
    "build_box_candidates",
    "empty_boxes",
    "sphere_centre",
]

Boxes = namedtuple(
    "Boxes",
    [
        "body",  # (nx,) int owner body
        "half",  # (nx, 3) core half-extents in the body frame [m]
        "radius",  # (nx,) rounding radius [m]
        "material",  # (nx,) int material id
        "normal_law",  # (1,) int: laws.hertz.LAW_LINEAR or LAW_HERTZ
        "rows",  # state.Contacts: the rows of the last step, box pairs then box-sphere pairs
        "next",  # state.Contacts being built (scratch)
        "m_normal",  # (MAX_POINTS, 3) scratch: the manifold of one pair (shapes.cuboid)
        "m_point",  # (MAX_POINTS, 3)
        "m_overlap",  # (MAX_POINTS,)
        "m_key",  # (MAX_POINTS,) int64
        "work",  # (2, 9, 4) clipping buffers
        "used",  # (K,) uint8 scratch: old rows matched this step
        "props",  # (5,) scratch: kn (Hertz: K), kt, mu, restitution, Tsuji alpha of a new point
        "n_changes",  # (1,) int64: body pairs whose contact started or ended this step
        "changes",  # (K, 3) int64: body i, body j or -(wall + 1), ONSET / END
        "change_lag",  # (K,) how long before this step's time it happened [s], in [0, dt]
        "cand",  # (P,) int64 candidate pairs (_pair_code), ascending (build_box_candidates)
        "n_cand",  # (1,) int64 candidates listed; -1: no list, every pair is a candidate
        "cand_start",  # (nx + 1,) int64 first candidate of each box (CSR of cand)
        "rev",  # (P,) int64 boxes a < b of the box-box candidates (a, b), by b (CSR)
        "rev_start",  # (nx + 1,) int64 first entry of each box b in rev
        "visit",  # (P,) int64 scratch: the candidates visited this step, ascending
        "src",  # (nx,) int64 scratch: the boxes a of the visited pairs, ascending
        "src_start",  # (nx + 1,) int64 scratch: first visited pair of each src entry
        "n_groups",  # (1,) int64: groups of visit/src/src_start, -1: to be rebuilt
        "held_at_build",  # (nx,) uint8: 1 if the box's pairs with held boxes and walls may
        #   be missing from cand (held at the list build; a new state: 1)
        "engaged",  # (nx,) uint8 scratch: a held box with a moving box among its visited
        #   candidates, which has its wall rows (_visit_pairs)
        "dormant",  # state.Contacts: the rows of the pairs of two resting bodies (held, or a
        #   wall), kept as they were while neither moves (_drop_before, _wake_rows)
        "order",  # (K,) int64 scratch of _wake_rows
        "restless",  # (nx,) uint8 scratch of engine._sleep_and_wake
        "partner_body",  # (nx + ns,) int64 the body of a row's partner j >= 0: box j < nx,
        #   sphere j - nx (the scene's spheres, by index)
        "sphere_cand",  # (Q,) int64 candidate box-sphere pairs, box * ns + sphere, ascending
        "n_sphere_cand",  # (1,) int64 candidates listed; -1: no list, every pair a candidate
        "sphere_cand_start",  # (nx + 1,) int64 first candidate of each box
    ],
)


def empty_boxes(body=(), half=(), radius=(), material=(), normal_law=LAW_LINEAR, sphere_body=()):
    """The box state of a scene (no box: zero-length arrays); ``normal_law`` one of
    laws.hertz.NORMAL_LAWS' values; ``sphere_body`` (ns,) the owners of the scene's
    spheres (room for rows of one contact of every sphere with each of up to 6 boxes: a
    box lying on a bed of spheres touches many of them)."""
    body = np.asarray(body, np.int64).reshape(-1)
    sphere_body = np.asarray(sphere_body, np.int64).reshape(-1)
    nx = body.shape[0]
    capacity = 32 * nx + 32
    sphere_capacity = capacity + min(nx, 6) * sphere_body.shape[0]
    rows = capacity + (sphere_capacity if sphere_body.shape[0] else 0)
    return Boxes(
        body=body,
        half=np.asarray(half, float).reshape(nx, 3),
        radius=np.asarray(radius, float).reshape(nx),
        material=np.asarray(material, np.int64).reshape(nx),
        normal_law=np.array([normal_law], np.int64),
        rows=empty_contacts(rows),
        next=empty_contacts(rows),
        m_normal=np.zeros((MAX_POINTS, 3)),
        m_point=np.zeros((MAX_POINTS, 3)),
        m_overlap=np.zeros(MAX_POINTS),
        m_key=np.zeros(MAX_POINTS, np.int64),
        work=np.zeros((2, 9, 4)),
        used=np.zeros(rows, np.uint8),
        props=np.zeros(5),
        n_changes=np.zeros(1, np.int64),
        changes=np.zeros((capacity + sphere_capacity, 3), np.int64),
        change_lag=np.zeros(capacity + sphere_capacity),
        cand=np.zeros(8 * nx + 16, np.int64),
        n_cand=np.full(1, -1, np.int64),
        cand_start=np.zeros(nx + 1, np.int64),
        rev=np.zeros(8 * nx + 16, np.int64),
        rev_start=np.zeros(nx + 1, np.int64),
        visit=np.zeros(8 * nx + 16, np.int64),
        src=np.zeros(nx, np.int64),
        src_start=np.zeros(nx + 1, np.int64),
        n_groups=np.full(1, -1, np.int64),
        held_at_build=np.ones(nx, np.uint8),
        engaged=np.zeros(nx, np.uint8),
        dormant=empty_contacts(capacity),
        order=np.zeros(capacity, np.int64),
        restless=np.zeros(nx, np.uint8),
        partner_body=np.concatenate((body, sphere_body)),
        sphere_cand=np.zeros(8 * nx + 16, np.int64),
        n_sphere_cand=np.full(1, -1, np.int64),
        sphere_cand_start=np.zeros(nx + 1, np.int64),
    )


@inline_kernel()
def inverse_mass_at(bodies, b, rx, ry, rz, n0, n1, n2):
    """``1/m + (r x n) . I^-1 (r x n)`` [1/kg] of body b at lever arm r, along n: the
    inverse of the mass that a force along n at r accelerates (Brach, Mechanical Impact
    Dynamics (1991) ch. 5).

    A blocked degree of freedom takes no share, as it takes no force: a blocked
    translation drops its ``n_k^2 / m`` (the momentum along it is the support's), and only
    the free rotations count (``rot_mode``: one axis, none; a sphere's blocked spin
    components).  A body with every degree of freedom blocked gives 0, as a wall.  (Where
    the normal has no component along the blocked axes -- a planar scene's normals and
    its blocked y -- this is ``1/m`` exactly.)"""
    c0 = ry * n2 - rz * n1
    c1 = rz * n0 - rx * n2
    c2 = rx * n1 - ry * n0
    blocked = bodies.blocked[b]
    inv = 1.0 / bodies.mass[b]
    if blocked[0] * n0 * n0 + blocked[1] * n1 * n1 + blocked[2] * n2 * n2 > 0.0:
        free = (1 - blocked[0]) * n0 * n0 + (1 - blocked[1]) * n1 * n1
        inv = (free + (1 - blocked[2]) * n2 * n2) / bodies.mass[b]
    mode = bodies.rot_mode[b]
    if mode == ROT_FREE:
        R = bodies.rot[b]
        for k in range(3):
            ck = R[0, k] * c0 + R[1, k] * c1 + R[2, k] * c2
            inv += ck * ck / bodies.inertia[b, k]
    elif mode == ROT_AXIS:
        a = bodies.axis[b]
        ca = a[0] * c0 + a[1] * c1 + a[2] * c2
        inv += ca * ca / bodies.axis_inertia[b]
    elif mode == ROT_ISOTROPIC:
        if blocked[3] or blocked[4] or blocked[5]:
            c0, c1, c2 = (1 - blocked[3]) * c0, (1 - blocked[4]) * c1, (1 - blocked[5]) * c2
        inv += (c0 * c0 + c1 * c1 + c2 * c2) / bodies.inertia[b, 0]
    return inv


@inline_kernel()
def _reach_of(boxes, x):
    """Bounding radius [m] of box x: its core's half-diagonal plus the rounding."""
    h = boxes.half[x]
    return math.sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]) + boxes.radius[x]


# (allocates: compiled with numba's reference counting, dem/compiled.py)
@inner_kernel(_nrt=True)
def build_box_candidates(bodies, boxes, walls, skin):
    """The neighbour list of the box contacts: the box-box and box-wall pairs whose
    bounding spheres come closer than ``skin`` [m], into ``boxes.cand`` (ascending
    :func:`_pair_code`) and ``boxes.cand_start``.  Returns their number, or ``-needed``
    if ``boxes.cand`` is too short (then ``n_cand`` is -1: every pair is a candidate
    until the caller grows it and builds again).

    While at most half of the boxes move, the pairs that get no rows while the list
    lasts are left out -- two held boxes, a held box that no moving box is near and a wall
    (:func:`_held_pair`) -- and the search looks only around the boxes that are not held
    (contact._scan_cells with them active: every neighbour cell of each), and at the
    walls of the held boxes it finds: it costs what the moving part of a chain held until
    touched costs.
    ``boxes.held_at_build`` marks the boxes held then; the engine builds
    the list again at the step after one of them is released (or at the start of a run
    in which it is free, :func:`released_since_build`).  With more boxes moving, every
    pair is listed (the half-shell search over all boxes, contact._scan_cells, is the
    cheaper one then) and no box is marked.

    The bounding sphere of box x has the radius ``reach_x + r_x`` (core half-diagonal plus
    twice the rounding), which covers the tests of :func:`box_forces` with their margins:
    two boxes pass them only closer than ``reach_a + reach_b + (r_a + r_b) / 2``, a box
    and a wall only closer than its support plus ``r``, at most ``reach + r``.  Between
    builds no core point moves more than skin/2 (contact.needs_rebuild, with the core
    half-diagonal as the body's extent), so no pair outside the list can pass them.
    """
    nx = boxes.body.shape[0]
    boxes.n_groups[0] = -1  # (the visited pairs come from the list)
    pos = np.empty((nx, 3))
    radius = np.empty(nx)
    for x in range(nx):
        for d in range(3):
            pos[x, d] = bodies.pos[boxes.body[x], d]
        radius[x] = _reach_of(boxes, x) + boxes.radius[x]
    # (the bounding spheres as the spheres of the sphere search: one per body)
    bound = Spheres(
        body=boxes.body,
        radius=radius,
        local=pos,
        material=boxes.material,
        pos=pos,
        listed=boxes.body,
        n_listed=boxes.n_cand,
    )
    moving = np.empty(nx, np.uint8)
    n_moving = 0
    for x in range(nx):
        moving[x] = 0 if bodies.held[boxes.body[x]] else 1
        n_moving += moving[x]
    if 2 * n_moving <= nx:
        keys, _ = _candidate_pairs(bound, walls, skin, moving)
        keys = _with_neighbour_walls(bound, walls, skin, moving, keys)
        for x in range(nx):
            boxes.held_at_build[x] = 1 - moving[x]
    else:
        keys, _ = _candidate_pairs(bound, walls, skin)
        boxes.held_at_build[:] = 0
    n = keys.shape[0]
    if n > boxes.cand.shape[0]:
        boxes.n_cand[0] = -1
        return -n
    stride = nx + walls.point.shape[0]
    start, rev_start = boxes.cand_start, boxes.rev_start
    start[:] = 0
    rev_start[:] = 0
    for k in range(n):
        boxes.cand[k] = keys[k]
        start[keys[k] // stride + 1] += 1
        b = keys[k] % stride
        if b < nx:
            rev_start[b + 1] += 1
    for x in range(nx):
        start[x + 1] += start[x]
        rev_start[x + 1] += rev_start[x]
    # (the reverse lists: keys ascend, so each box's boxes a come in ascending order)
    fill = rev_start[:nx].copy()
    for k in range(n):
        b = keys[k] % stride
        if b < nx:
            boxes.rev[fill[b]] = keys[k] // stride
            fill[b] += 1
    boxes.n_cand[0] = n
    return n


@inner_kernel(_nrt=True)
def _with_neighbour_walls(bound, walls, skin, moving, keys):
    """``keys`` (ascending pair codes of the pairs with a moving box, ``moving`` (nx,)
    uint8) with the wall pairs of the held boxes among them added, ascending: a held box
    next to a moving one gets its wall rows before the step that releases it
    (:func:`_visit_pairs`)."""
    nx = moving.shape[0]
    nw = walls.point.shape[0]
    stride = nx + nw
    neighbour = np.zeros(nx, np.uint8)
    for k in range(keys.shape[0]):
        a, j = keys[k] // stride, keys[k] % stride
        if j < nx:
            neighbour[a] |= 1 - moving[a]
            neighbour[j] |= 1 - moving[j]
    raw = np.empty(nx * nw + 1, np.int64)
    first = np.empty(raw.shape[0], np.int64)
    n = _scan_walls(bound, walls, skin, neighbour, raw, first, 0)
    if n == 0:
        return keys
    return np.sort(np.concatenate((keys, raw[:n])))


@inline_kernel()
def released_since_build(bodies, boxes):
    """True if a box held at the last list build is free now: its pairs with held boxes
    and walls may be missing from the list (:func:`build_box_candidates`), which must be
    built again before the next :func:`box_forces`."""
    for x in range(boxes.body.shape[0]):
        if boxes.held_at_build[x] and not bodies.held[boxes.body[x]]:
            return True
    return False


@inline_kernel()
def held_flags_changed(bodies, boxes):
    """The held flags changed (a release, a sleep, or the caller between runs): the
    visited pairs are built anew (:func:`_visit_pairs`), and the list too, at the next
    step, if it leaves out pairs of a box free now (:func:`released_since_build`)."""
    boxes.n_groups[0] = -1
    if released_since_build(bodies, boxes):
        boxes.n_cand[0] = -1


@inner_kernel(_nrt=False)
def _visit_pairs(bodies, boxes, nx, nw):
    """The listed candidate pairs that are not held pairs (:func:`_held_pair`), ascending,
    into ``boxes.visit``, grouped by their first box (``boxes.src``, ``boxes.src_start``);
    returns the number of groups, or ``nx`` without a list (every box a source, every
    pair a candidate: :func:`_partner_range`; no box engaged).

    A held box with a moving box among its candidates is *engaged* (``boxes.engaged``):
    its wall pairs are visited too, so that it stands on the floor in the step a moving
    box first touches it, as a free box at rest does; the release after that step's
    forces (engine._bookkeep) then changes nothing but the flag.  Its wall rows
    act on a held body, which does not move, until then.

    The visited pairs change only when the list is built or a box is released, so they
    are kept from step to step (``boxes.n_groups``) and built again only after
    ``n_groups`` is set to -1: by :func:`build_box_candidates`, by the engine after every
    step that released a held body and at the start of every run (a caller may have
    changed the held flags), and by :func:`box_forces` at a first step.

    Only the boxes that are not held are looked at -- each with its own candidates
    (a, j > a) and walls, and the held boxes a < b of its reverse list (``boxes.rev``) --
    so a held box costs one test, however many candidates it has (a list that leaves
    out the pairs of held boxes, :func:`build_box_candidates`, has none to skip).  Each
    candidate is in exactly one of those lists,
    and the sort restores the pair order of the list (a reverse pair (a, b) comes before
    b's own pairs): the pairs are visited in the order of the full list, so the forces
    are the same to the bit."""
    engaged = boxes.engaged
    if boxes.n_cand[0] < 0:
        engaged[:] = 0
        return nx
    if boxes.n_groups[0] >= 0:
        return boxes.n_groups[0]
    held, body = bodies.held, boxes.body
    visit, cand, rev = boxes.visit, boxes.cand, boxes.rev
    stride = nx + nw
    engaged[:] = 0
    for b in range(nx):
        if held[body[b]]:
            continue
        for k in range(boxes.rev_start[b], boxes.rev_start[b + 1]):
            engaged[rev[k]] |= held[body[rev[k]]]
        for k in range(boxes.cand_start[b], boxes.cand_start[b + 1]):
            j = cand[k] % stride
            if j < nx:
                engaged[j] |= held[body[j]]
    n = 0
    for b in range(nx):
        if held[body[b]]:
            if engaged[b]:  # (its wall pairs: the list has them, _with_neighbour_walls)
                for k in range(boxes.cand_start[b], boxes.cand_start[b + 1]):
                    if cand[k] % stride >= nx:
                        visit[n] = cand[k]
                        n += 1
            continue
        for k in range(boxes.rev_start[b], boxes.rev_start[b + 1]):
            a = rev[k]
            if held[body[a]]:  # (a pair of two moving boxes is in a's own list)
                visit[n] = a * stride + b
                n += 1
        for k in range(boxes.cand_start[b], boxes.cand_start[b + 1]):
            visit[n] = cand[k]
            n += 1
    # insertion sort: the reverse pairs of a box are the only ones out of order
    for k in range(1, n):
        code = visit[k]
        m = k - 1
        while m >= 0 and visit[m] > code:
            visit[m + 1] = visit[m]
            m -= 1
        visit[m + 1] = code
    n_src = 0
    for k in range(n):
        a = visit[k] // stride
        if n_src == 0 or boxes.src[n_src - 1] != a:
            boxes.src[n_src] = a
            boxes.src_start[n_src] = k
            n_src += 1
    boxes.src_start[n_src] = n
    boxes.n_groups[0] = n_src
    return n_src


@inline_kernel()
def _source(boxes, g):
    """Box a of group g of :func:`_visit_pairs` (without a list: box g)."""
    if boxes.n_cand[0] < 0:
        return g
    return boxes.src[g]


@inline_kernel()
def _partner_range(boxes, g, a, nx, nw):
    """Range of the partners to visit of box a, group g of :func:`_visit_pairs`: its
    visited candidates (:func:`_partner`), or, without a list, every box after it and
    every wall."""
    if boxes.n_cand[0] < 0:
        return a + 1, nx + nw
    return boxes.src_start[g], boxes.src_start[g + 1]


@inline_kernel()
def _partner(boxes, a, k, nx, nw):
    """Partner index ``jj`` (box ``jj`` < nx, wall ``jj - nx``) of entry k of box a's
    :func:`_partner_range`."""
    if boxes.n_cand[0] < 0:
        return k
    return boxes.visit[k] - a * (nx + nw)


@inline_kernel()
def _held_pair(bodies, boxes, a, bj, wall):
    """True if box ``a`` and its partner (body ``bj``, or a wall) get no contact rows
    because of held bodies (engine.py, held until touched): two held boxes, a held box
    with a wall unless the box is engaged (:func:`_visit_pairs`).  A held box is fixed,
    so these contacts could do no work; a moving body touching a held box gets its rows,
    whose onset releases the held box."""
    ba = boxes.body[a]
    if wall:
        return bodies.held[ba] == 1 and boxes.engaged[a] == 0
    return bodies.held[ba] == 1 and bodies.held[bj] == 1


@inline_kernel()
def _pair_code(i, j, nx, nw):
    """Sort key of the pair (box i, partner j): boxes j > i first, then the walls; a
    sphere partner (j >= nx) comes after every box pair (the box-sphere rows follow the
    others, in their own order: :func:`_box_sphere_pass`)."""
    if j >= nx:
        return nx * (nx + nw)
    return i * (nx + nw) + (j if j >= 0 else nx - j - 1)


@inner_kernel()
def _point_properties(boxes, walls, mats, a, j, out):
    """kn (Hertz: K), kt, mu, restitution, Tsuji alpha of a point of box a with partner j
    into ``out[0:5]``."""
    ma = boxes.material[a]
    ra = boxes.radius[a]
    if j >= 0:
        mb = boxes.material[j]
        rb = boxes.radius[j]
    else:
        mb = walls.material[-j - 1]
        rb = ra  # a wall takes the radius of the body touching it (as for spheres)
    material_pair(mats, ma, ra, mb, rb, out)
    if boxes.normal_law[0] == LAW_HERTZ:
        modulus = hertz_modulus(mats.young[ma], mats.poisson[ma], mats.young[mb], mats.poisson[mb])
        out[0] = hertz_coefficient(modulus, _hertz_radius(ra, rb, j < 0))
        out[4] = mats.hertz_damping[ma, mb]


@inline_kernel()
def _hertz_radius(ra, rb, wall):
    """R* [m] of a Hertz contact point (laws/hertz.py): ``r_a`` on a wall, ``2 r_a r_b / (r_a +
    r_b)`` between two boxes (= r for equal radii: a rounded vertex on a face, or two
    rounded edges crossing at a right angle)."""
    if wall:
        return ra
    return 2.0 * ra * rb / (ra + rb)


@inline_kernel()
def _continuation_distance(boxes, a, j):
    """Distance [m] within which a contact point of box a and partner j whose feature
    key changed continues an old point of the pair: half the smallest outer half-extent
    of the two bodies (the points of one manifold that stand for distinct contacts lie a
    face apart; a point moves by far less in one step)."""
    size = _thickness(boxes, a)
    if j >= 0:
        size = min(size, _thickness(boxes, j))
    return 0.5 * size


@inline_kernel()
def _thickness(boxes, x):
    """The smallest outer half-extent [m] of box x."""
    h = boxes.half[x]
    return min(h[0], h[1], h[2]) + boxes.radius[x]


@inner_kernel(_nrt=False)
def _continued_row(old, used, o, o_end, keys, m, p, tol):
    """The old row (of rows o .. o_end - 1, one pair) that a new touching point at p
    without a key match continues, or -1: the nearest row within ``tol`` [m] not yet
    matched whose key is not in this step's manifold (``keys[:m]``).  A point whose
    touching feature pair changes while it moves on continuously (a vertex sliding off a
    face over the rounded edge: a face-clip point, then a vertex-edge point) so keeps its
    shear history."""
    q, best = -1, tol * tol
    for t in range(o, o_end):
        if used[t]:
            continue
        claimed = False
        for k in range(m):
            if keys[k] == old.key[t]:
                claimed = True
                break
        if claimed:
            continue
        d2 = 0.0
        for d in range(3):
            d2 += (old.point[t, d] - p[d]) ** 2
        if d2 < best:
            q, best = t, d2
    return q


@inner_kernel(_nrt=False)
def _release(old, q, ledger):
    """Old row q is gone without an end step (its feature left the manifold): the energy
    of its shear spring is released by slip (booked as friction)."""
    u = old.shear[q]
    ledger[LEDGER_FRICTION] += 0.5 * old.mult[q] * old.kt[q] * (u[0] ** 2 + u[1] ** 2 + u[2] ** 2)


@inline_kernel()
def _apply(bodies, b, p, f0, f1, f2, sign):
    """Add ``sign f`` acting at the point p to the force and torque of body b."""
    rx, ry, rz = p[0] - bodies.pos[b, 0], p[1] - bodies.pos[b, 1], p[2] - bodies.pos[b, 2]
    apply_at_lever(bodies, b, rx, ry, rz, f0, f1, f2, sign)


@inner_kernel(_nrt=False)
def _end(bodies, old, q, gap, dt, bi, bj, wall, ledger, hertz):
    """Old row q opened in the last drift (now ``gap <= 0``): the end impulse the last kick
    missed (laws.linear.end_impulse; none for the Hertz law, whose force vanishes smoothly),
    and the release of its shear spring."""
    f_el, f_visc = 0.0, 0.0
    if not hertz:
        f_el, f_visc = end_impulse(old.overlap[q], gap, old.kn[q], old.cn[q], dt)
    fn = (f_el + f_visc) * old.mult[q]
    if fn != 0.0:
        n = old.normal[q]
        p = old.point[q]
        if not wall:
            _apply(bodies, bj, p, fn * n[0], fn * n[1], fn * n[2], 1.0)
        _apply(bodies, bi, p, fn * n[0], fn * n[1], fn * n[2], -1.0)
    _release(old, q, ledger)


@inline_kernel()
def _spin(omega, ba, bj, wall, n0, n1, n2):
    """Sum [rad/s] of the angular velocities of body ``ba`` and its partner (body ``bj``,
    or a fixed wall) along the normal n."""
    spin = n0 * omega[ba, 0] + n1 * omega[ba, 1] + n2 * omega[ba, 2]
    if not wall:
        spin += n0 * omega[bj, 0] + n1 * omega[bj, 1] + n2 * omega[bj, 2]
    return spin


@inline_kernel()
def _open_row(new, c, a, j, key, mult, normal, point):
    """Row c of ``new``: the point of box a with partner j (box, wall -(w + 1) or sphere
    ``nx + s``), its feature key, multiplicity, unit normal (3,) and
    position (3,) [m]; :func:`_point_row` fills in the rest."""
    if c == new.i.shape[0]:
        raise RuntimeError("box contact rows full")
    new.i[c] = a
    new.j[c] = j
    new.key[c] = key
    new.mult[c] = mult
    for d in range(3):
        new.normal[c, d] = normal[d]
        new.point[c, d] = point[d]


@inline_kernel()
def _point_row(bodies, old, new, c, q, props, ba, bj, wall, overlap, dt, first_step, hertz, ledger):
    """The contact law (laws.point.point_law) at the point of row c of ``new`` between body
    ``ba`` (the box) and its partner (body ``bj``, or a wall), for every kind of partner
    (box_forces, _box_sphere_pass).  The row's pair, key, multiplicity, normal and point are
    written; it continues old row q, or is a fresh point (q < 0) with the constants
    ``props`` (kn or Hertz K, kt, mu, restitution, Tsuji alpha) and its dashpot from the
    effective mass at the point along the normal (:func:`inverse_mass_at` of both
    bodies).  Writes the row's state (constants, shear, overlap, normal velocity, forces),
    applies ``mult`` times the point's force to the bodies (a planar row stands for
    ``mult`` points) and books its slip in ``ledger[LEDGER_FRICTION]``."""
    n0, n1, n2 = new.normal[c, 0], new.normal[c, 1], new.normal[c, 2]
    p = new.point[c]
    mult = new.mult[c]
    fresh = q < 0
    if fresh:
        new.kn[c], new.kt[c], new.mu[c] = props[0], props[1], props[2]
        inv = inverse_mass_at(
            bodies, ba, p[0] - bodies.pos[ba, 0], p[1] - bodies.pos[ba, 1],
            p[2] - bodies.pos[ba, 2], n0, n1, n2,
        )  # fmt: skip
        if not wall:
            inv += inverse_mass_at(
                bodies, bj, p[0] - bodies.pos[bj, 0], p[1] - bodies.pos[bj, 1],
                p[2] - bodies.pos[bj, 2], n0, n1, n2,
            )  # fmt: skip
        # (each point its own dashpot, as for a single-point impact; a planar row stands
        # for mult such points)
        new.cn[c] = onset_dashpot(new.kn[c], props[3], props[4], inv, hertz)
        u0 = u1 = u2 = 0.0
        vn_old = 0.0
    else:
        new.kn[c], new.kt[c], new.mu[c], new.cn[c] = old.kn[q], old.kt[q], old.mu[q], old.cn[q]
        u0, u1, u2 = old.shear[q, 0], old.shear[q, 1], old.shear[q, 2]
        vn_old = old.vn[q]
    dv0, dv1, dv2 = relative_velocity(bodies, bodies.vel, bodies.omega, ba, bj, wall, p)
    spin = _spin(bodies.omega, ba, bj, wall, n0, n1, n2)
    fn, fn_viscous, vn, u0, u1, u2, released, f0, f1, f2 = point_law(
        overlap, n0, n1, n2, dv0, dv1, dv2, dv0, dv1, dv2, 0.5 * spin * dt, u0, u1, u2,
        vn_old, fresh, new.kn[c], new.kt[c], new.mu[c], new.cn[c], dt, first_step, hertz,
    )  # fmt: skip
    new.shear[c, 0], new.shear[c, 1], new.shear[c, 2] = u0, u1, u2
    ledger[LEDGER_FRICTION] += mult * released
    new.overlap[c] = overlap
    new.vn[c] = vn
    new.fn[c] = fn
    new.fn_viscous[c] = fn_viscous
    f0, f1, f2 = mult * f0, mult * f1, mult * f2
    if not wall:
        _apply(bodies, bj, p, f0, f1, f2, 1.0)
    _apply(bodies, ba, p, f0, f1, f2, -1.0)


@inline_kernel()
def _log(boxes, a, j, kind, lag):
    """Record that the contact of box a's body with partner j (box, sphere ``nx + s`` or
    -(wall + 1)) started (ONSET) or ended (END) ``lag`` [s] before this step
    (``boxes.changes``, in the order of the rows: contact_rows.log_change)."""
    bj = boxes.partner_body[j] if j >= 0 else j
    n = boxes.n_changes[0]
    boxes.n_changes[0] = log_change(
        boxes.changes, boxes.change_lag, n, boxes.body[a], bj, kind, lag
    )


def _box_geometry(PLANAR):  # (capital: a constant of the compiled kernels)
    """The bounding tests and the manifold of a box pair in a scene of the kind ``PLANAR``
    (one source, compiled once for each kind, as contact._sphere_driver): those of a
    planar scene call only the planar geometry (shapes.rectangle), those of a general
    scene only the 3D one (shapes.cuboid), so that a scene compiles only its own.
    Returns ``(within_reach, manifold)``."""

    # (inlined, as the other helpers box_forces calls for every pair or step: a call of a
    # compiled function passes every array of its tuple arguments one by one,
    # benchmarks/README.md, "Rounded-cuboid contacts", item (8))
    @inline_kernel()
    def manifold(bodies, boxes, walls, a, j, margin, frame_ready):
        """Contact points of box a with partner j (box, or -(wall + 1)) into boxes.m_*;
        returns their number.  ``frame_ready``: ``within_reach`` has just passed this
        pair, and nothing has written ``boxes.work`` since -- two boxes in 3D then take the
        relative frame that its face test left there (shapes.cuboid.box_box)."""
        normal, point, overlap, keyf = boxes.m_normal, boxes.m_point, boxes.m_overlap, boxes.m_key
        ba = boxes.body[a]
        xa, Ra, ha, ra = bodies.pos[ba], bodies.rot[ba], boxes.half[a], boxes.radius[a]
        if j >= 0:
            bb = boxes.body[j]
            xb, Rb, hb, rb = bodies.pos[bb], bodies.rot[bb], boxes.half[j], boxes.radius[j]
            if PLANAR:
                n = rect_rect(xa, Ra, ha, ra, xb, Rb, hb, rb, margin, normal, point, overlap, keyf)
            else:
                n = box_box(
                    xa, Ra, ha, ra, xb, Rb, hb, rb, margin, boxes.work, normal, point, overlap,
                    keyf, frame_ready,
                )  # fmt: skip
        else:
            w = -j - 1
            p0, nw = walls.point[w], walls.normal[w]
            if PLANAR:
                n = rect_plane(xa, Ra, ha, ra, p0, nw, margin, normal, point, overlap, keyf)
            else:
                n = box_plane(xa, Ra, ha, ra, p0, nw, margin, normal, point, overlap, keyf)
        return n

    @inline_kernel()
    def within_reach(bodies, boxes, walls, a, j):
        """The margin [m] of the manifold of box a with partner j (box, or -(wall + 1)) if the
        pair may touch, else -1: the held test (:func:`_held_pair`), then for a wall the
        support of the box along the wall normal, ``r + sum_m h_m |n . R_m|``, against its
        distance; for two boxes their bounding spheres, then the face axes of both (the first
        exit of the manifold's separating-axis test, without the call: most boxes within
        their bounding spheres are apart, the spheres of a domino being 10 times as wide as
        it is thick)."""
        ba = boxes.body[a]
        wall = j < 0
        if _held_pair(bodies, boxes, a, boxes.body[j] if not wall else ba, wall):
            return -1.0
        if wall:
            w = -j - 1
            nw_ = walls.normal[w]
            ha = boxes.half[a]
            R = bodies.rot[ba]
            support = boxes.radius[a]
            for m in range(3):
                support += ha[m] * abs(nw_[0] * R[0, m] + nw_[1] * R[1, m] + nw_[2] * R[2, m])
            dist = 0.0
            for d in range(3):
                dist += (bodies.pos[ba, d] - walls.point[w, d]) * nw_[d]
            margin = boxes.radius[a]
            if dist - support >= margin:
                return -1.0
        else:
            bj = boxes.body[j]
            margin = 0.5 * (boxes.radius[a] + boxes.radius[j])
            d2 = 0.0
            for d in range(3):
                d2 += (bodies.pos[bj, d] - bodies.pos[ba, d]) ** 2
            if d2 >= (_reach_of(boxes, a) + _reach_of(boxes, j) + margin) ** 2:
                return -1.0
            xa, Ra, ha = bodies.pos[ba], bodies.rot[ba], boxes.half[a]
            xb, Rb, hb = bodies.pos[bj], bodies.rot[bj], boxes.half[j]
            reach = boxes.radius[a] + boxes.radius[j] + margin
            if PLANAR:
                if edges_separate(xa, Ra, ha, xb, Rb, hb, reach):
                    return -1.0
            elif faces_separate(xa, Ra, ha, xb, Rb, hb, reach, boxes.work):
                return -1.0
        return margin

    return within_reach, manifold


_within_reach_planar, _manifold_planar = _box_geometry(True)
_within_reach_general, _manifold_general = _box_geometry(False)


@inline_kernel()
def sphere_centre(bodies, spheres, s, out):
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
def _sphere_margin(boxes, spheres, a, s):
    """Margin [m] of the contact point of box a and sphere s: half the smaller of the
    sphere's radius and the box's smallest outer half-extent (a point moves far less in
    one step)."""
    return 0.5 * min(_thickness(boxes, a), spheres.radius[s])


@inline_kernel()
def _sphere_code(old, o, nx, ns):
    """Sort key ``box * ns + sphere`` of old box-sphere row o (partner ``j = nx + s``)."""
    return old.i[o] * ns + old.j[o] - nx


@inner_kernel(_nrt=False)
def _drop_sphere_rows(old, boxes, o, code, nx, ns, ledger):
    """Old box-sphere rows from o on of pairs before ``code`` are out of reach: release
    their shear springs, log their ends; returns the first row of ``code`` or after."""
    while o < old.n[0] and _sphere_code(old, o, nx, ns) < code:
        _release(old, o, ledger)
        _log(boxes, old.i[o], old.j[o], END, 0.0)
        o += 1
    return o


def _box_sphere_pass(PLANAR):  # (capital: a constant of the compiled kernel)
    """The box-sphere pass of :func:`box_forces` in a scene of the kind ``PLANAR``: the
    planar geometry (shapes.rectangle.rect_sphere) or the 3D one
    (shapes.cuboid.box_sphere)."""

    @inner_kernel(_nrt=False)
    def sphere_pass(bodies, spheres, boxes, mats, old, new, o, n_new, dt, ledger, first_step):
        """The box-sphere points of this step, after those of the box pairs: new rows from
        ``n_new`` on, continuing the old ones from row ``o`` on (partner ``j = nx + s``,
        in pair order: box, then sphere); returns the number of new rows.

        A sphere touches a convex box at one point (``box_sphere`` or ``rect_sphere``:
        the sphere's centre against the core box, overlap ``r_box + R - distance``, the
        face, edge or vertex region implicit), so the pair is its own key, and a planar
        row stands for one point (no doubling along y).  The law is the box points'
        (:func:`_point_row`), with the material pair of the rounding and the sphere's
        radius; Hertz scenes hold no spheres (``Scene.build`` refuses them), so it is the
        linear one.  The pairs visited are the candidates of
        box_sphere.build_box_sphere_candidates (or every pair without a list: the same
        pairs pass, in the same order) whose sphere's centre is closer to the box's
        centre than the box's reach plus ``R`` plus the margin (:func:`_sphere_margin`,
        so that a point is seen opening: its end impulse); a pair of two held bodies is
        not visited."""
        nx = boxes.body.shape[0]
        ns = spheres.body.shape[0]
        props = boxes.props
        c_s = boxes.work[0, 0, :3]  # (scratch: the sphere's centre)
        listed = boxes.n_sphere_cand[0] >= 0
        start = boxes.sphere_cand_start
        for a in range(nx):
            lo, hi = (start[a], start[a + 1]) if listed else (0, ns)
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
                sphere_centre(bodies, spheres, s, c_s)
                radius = spheres.radius[s]
                margin = _sphere_margin(boxes, spheres, a, s)
                d2 = 0.0
                for d in range(3):
                    d2 += (c_s[d] - xa[d]) ** 2
                if d2 >= (reach + radius + margin) ** 2:
                    continue
                code = a * ns + s
                o = _drop_sphere_rows(old, boxes, o, code, nx, ns, ledger)
                q = o if o < old.n[0] and _sphere_code(old, o, nx, ns) == code else -1
                if q >= 0:
                    o += 1
                if PLANAR:
                    m = rect_sphere(xa, Ra, ha, ra, c_s, radius, margin, boxes.m_normal,
                                    boxes.m_point, boxes.m_overlap, boxes.m_key)  # fmt: skip
                else:
                    m = box_sphere(xa, Ra, ha, ra, c_s, radius, margin, boxes.m_normal,
                                   boxes.m_point, boxes.m_overlap, boxes.m_key)  # fmt: skip
                overlap = boxes.m_overlap[0] if m > 0 else -margin
                j = nx + s
                if overlap <= 0.0:
                    if q >= 0:
                        if m > 0:
                            _end(bodies, old, q, overlap, dt, ba, bs, False, ledger, False)
                        else:
                            _release(old, q, ledger)
                        speed = (old.overlap[q] - overlap) / dt
                        _log(boxes, a, j, END, event_lag(overlap, speed, dt, first_step))
                    continue
                c = n_new
                n_new += 1
                _open_row(new, c, a, j, 0, 1.0, boxes.m_normal[0], boxes.m_point[0])
                fresh = q < 0
                if fresh:
                    material_pair(mats, boxes.material[a], ra, spheres.material[s], radius, props)
                _point_row(bodies, old, new, c, q, props, ba, bs, False, overlap, dt, first_step,
                           False, ledger)  # fmt: skip
                if fresh:
                    _log(boxes, a, j, ONSET, event_lag(overlap, -new.vn[c], dt, first_step))
        _drop_sphere_rows(old, boxes, o, 2**62, nx, ns, ledger)
        return n_new

    return sphere_pass


_sphere_pass_planar = _box_sphere_pass(True)
_sphere_pass_general = _box_sphere_pass(False)


def _box_driver(PLANAR, SPHERES):  # (capitals: constants of the compiled kernel)
    """:func:`box_forces` of a scene of the kind ``PLANAR``, with its kind's geometry
    (:func:`_box_geometry`; module-level names, so that the closure holds only the
    constants: numba keys a closure's disk cache by what it holds, and a kernel it held
    would key it by a number drawn anew in every process); with the box-sphere points
    (:func:`_box_sphere_pass`) if ``SPHERES``, so that a scene of boxes alone does not
    compile them."""

    # (inlined into the engine's loop: a call passes every array of the bodies and the box
    # state one by one; see manifold)
    @inline_kernel()
    def forces(bodies, spheres, boxes, walls, mats, dt, ledger, first_step):
        """Add the forces and torques of every box contact to the bodies (after
        contact.compute_forces, which zeroes them), rebuild the contact rows, book the change
        of the energy stored in the shear springs in ``ledger[LEDGER_FRICTION]``.  Body pairs
        whose contact (any point) started or ended are listed in ``boxes.changes``.  The
        rows are those of the box-box and box-wall pairs, in pair order, then those of the
        box-sphere pairs (:func:`_box_sphere_pass`), in one table.

        The rows of a pair of resting bodies -- two held boxes, or a held box and a wall,
        that have rows: bodies put to sleep (engine._sleep_and_wake) -- are not visited; they
        are kept aside as they were (``boxes.dormant``), with no end logged, and merged back
        when the visited pairs are built anew after a body of one of them woke
        (:func:`_wake_rows`): a pair visited again continues its rows, shear springs and all."""
        boxes.n_changes[0] = 0
        nx = boxes.body.shape[0]
        nw = walls.point.shape[0]
        if first_step:  # (the held flags may be new: _visit_pairs)
            boxes.n_groups[0] = -1
        visited_anew = boxes.n_groups[0] < 0
        n_groups = _visit_pairs(bodies, boxes, nx, nw)  # (and which held boxes are engaged)
        if visited_anew and _woken(bodies, boxes):
            _wake_rows(boxes, nx, nw)
        old, new = boxes.rows, boxes.next
        within_reach = _within_reach_planar if PLANAR else _within_reach_general
        manifold = _manifold_planar if PLANAR else _manifold_general
        used = boxes.used
        used[: old.n[0]] = 0
        props = boxes.props
        hertz = boxes.normal_law[0] == LAW_HERTZ
        o = 0
        n_new = 0
        for g in range(n_groups):
            a = _source(boxes, g)
            ba = boxes.body[a]
            lo, hi = _partner_range(boxes, g, a, nx, nw)
            for kk in range(lo, hi):
                jj = _partner(boxes, a, kk, nx, nw)
                j = jj if jj < nx else -(jj - nx) - 1
                wall = j < 0
                margin = within_reach(bodies, boxes, walls, a, j)
                if margin < 0.0:
                    continue
                bj = ba if wall else boxes.body[j]
                mult = multiplicity(boxes.half[a], boxes.half[a if wall else j]) if PLANAR else 1.0
                code = _pair_code(a, j, nx, nw)
                # old rows of pairs before this one are gone: release their springs
                o = _drop_before(bodies, old, boxes, o, code, nx, nw, ledger)
                o_end = o
                while o_end < old.n[0] and _pair_code(old.i[o_end], old.j[o_end], nx, nw) == code:
                    o_end += 1
                m = manifold(bodies, boxes, walls, a, j, margin, True)  # (within_reach)
                tol = _continuation_distance(boxes, a, j)
                first_row = n_new
                end_depth, end_speed = 0.0, 0.0
                for k in range(m):
                    key = boxes.m_key[k]
                    q = -1
                    for t in range(o, o_end):
                        if old.key[t] == key and not used[t]:
                            q = t
                            break
                    overlap = boxes.m_overlap[k]
                    # only a touching point continues another feature's row: a point out of
                    # contact has no spring to carry, and its gap is not the continuation of
                    # the old point's overlap (the end impulse would read the jump between the
                    # two features as a separation speed, ramp / dt, and kick the pair apart)
                    if q < 0 and overlap > 0.0:
                        q = _continued_row(
                            old, used, o, o_end, boxes.m_key, m, boxes.m_point[k], tol
                        )
                    if overlap <= 0.0:
                        if q >= 0:
                            used[q] = 1
                            _end(bodies, old, q, overlap, dt, ba, bj, wall, ledger, hertz)
                            if old.overlap[q] - overlap > end_speed * dt:
                                end_depth, end_speed = overlap, (old.overlap[q] - overlap) / dt
                        continue
                    c = n_new
                    n_new += 1
                    _open_row(new, c, a, j, key, mult, boxes.m_normal[k], boxes.m_point[k])
                    if q < 0:
                        _point_properties(boxes, walls, mats, a, j, props)
                    else:
                        used[q] = 1
                    _point_row(bodies, old, new, c, q, props, ba, bj, wall, overlap, dt, first_step,
                               hertz, ledger)  # fmt: skip
                # rows of this pair whose feature left the manifold
                for t in range(o, o_end):
                    if not used[t]:
                        used[t] = 1
                        _release(old, t, ledger)
                if o_end == o and n_new > first_row:
                    deepest = first_row
                    for c in range(first_row, n_new):
                        if new.overlap[c] > new.overlap[deepest]:
                            deepest = c
                    lag = event_lag(new.overlap[deepest], -new.vn[deepest], dt, first_step)
                    _log(boxes, a, j, ONSET, lag)
                elif o_end > o and n_new == first_row:
                    _log(boxes, a, j, END, event_lag(end_depth, end_speed, dt, first_step))
                o = o_end
        # (the old rows of the box pairs end where those of the sphere partners begin)
        o = _drop_before(bodies, old, boxes, o, nx * (nx + nw), nx, nw, ledger)
        if SPHERES:
            sphere_pass = _sphere_pass_planar if PLANAR else _sphere_pass_general
            n_new = sphere_pass(
                bodies, spheres, boxes, mats, old, new, o, n_new, dt, ledger, first_step
            )
        _copy_rows(new, old, n_new)

    return forces


box_forces_planar = _box_driver(True, False)
box_forces_general = _box_driver(False, False)
box_forces_planar_spheres = _box_driver(True, True)
box_forces_general_spheres = _box_driver(False, True)


@inline_kernel(python_entry=True)
def _within_reach(bodies, boxes, walls, a, j, planar):
    """The bounding tests of the pair (box a, partner j) in a scene of the kind ``planar``
    (:func:`_box_geometry`), for the benchmarks."""
    if planar:
        return _within_reach_planar(bodies, boxes, walls, a, j)
    return _within_reach_general(bodies, boxes, walls, a, j)


@inline_kernel()
def _manifold(bodies, boxes, walls, a, j, planar, margin, frame_ready):
    """The manifold of the pair (box a, partner j) in a scene of the kind ``planar``
    (:func:`_box_geometry`), for the benchmarks."""
    if planar:
        return _manifold_planar(bodies, boxes, walls, a, j, margin, frame_ready)
    return _manifold_general(bodies, boxes, walls, a, j, margin, frame_ready)


@inline_kernel()
def box_forces(bodies, spheres, boxes, walls, mats, dt, ledger, first_step, planar):
    """The box driver of a scene of the kind ``planar``, with the box-sphere points if it
    has spheres (the time loop calls its kind's; this is for the benchmarks)."""
    if spheres.body.shape[0] > 0:
        if planar:
            box_forces_planar_spheres(bodies, spheres, boxes, walls, mats, dt, ledger, first_step)
        else:
            box_forces_general_spheres(bodies, spheres, boxes, walls, mats, dt, ledger, first_step)
    elif planar:
        box_forces_planar(bodies, spheres, boxes, walls, mats, dt, ledger, first_step)
    else:
        box_forces_general(bodies, spheres, boxes, walls, mats, dt, ledger, first_step)


@inline_kernel()
def _drop_before(bodies, old, boxes, o, code, nx, nw, ledger):
    """Old rows from o on of the pairs before ``code`` were not visited: a pair of resting
    bodies (:func:`_resting_pair`) keeps them aside (``boxes.dormant``); any other pair is
    out of reach: release their springs and log the end of each such pair.  Returns the
    first row of ``code`` or after."""
    used = boxes.used
    while o < old.n[0] and _pair_code(old.i[o], old.j[o], nx, nw) < code:
        if _resting_pair(bodies, boxes, old.i[o], old.j[o]):
            d = boxes.dormant.n[0]
            if d == boxes.dormant.i.shape[0]:
                raise RuntimeError("dormant box contact rows full")
            copy_row(old, o, boxes.dormant, d)
            boxes.dormant.n[0] = d + 1
            o += 1
            continue
        if not used[o]:
            _release(old, o, ledger)
        if o + 1 == old.n[0] or old.i[o + 1] != old.i[o] or old.j[o + 1] != old.j[o]:
            _log(boxes, old.i[o], old.j[o], END, 0.0)
        o += 1
    return o


@inline_kernel()
def _resting_pair(bodies, boxes, i, j):
    """True if box i and its partner j (box, or -(wall + 1)) are not visited because of
    held bodies (:func:`_held_pair`): a pair of them that has rows rests (a held box gets
    rows only while a moving body is near, or asleep)."""
    wall = j < 0
    return _held_pair(bodies, boxes, i, boxes.body[i] if wall else boxes.body[j], wall)


@inline_kernel()
def _copy_rows(src, dst, n):
    for c in range(n):
        copy_row(src, c, dst, c)
    dst.n[0] = n


@inline_kernel()
def _woken(bodies, boxes):
    """True if a dormant row's pair no longer rests (a body of it woke, or a held box of
    it is engaged: :func:`_visit_pairs`, called before)."""
    dormant = boxes.dormant
    for c in range(dormant.n[0]):
        if not _resting_pair(bodies, boxes, dormant.i[c], dormant.j[c]):
            return True
    return False


@inner_kernel(_nrt=False)
def _wake_rows(boxes, nx, nw):
    """Merge the dormant rows (:func:`box_forces`) back into ``boxes.rows``, in pair order
    (through ``boxes.next``); the pairs still resting are put aside again by the next
    :func:`box_forces`.  The dormant rows are sorted first (a stable insertion sort of
    their indices: they were put aside in pair order, step after step, so they are
    nearly sorted); a pair's rows are in one table only."""
    dormant, old, new, order = boxes.dormant, boxes.rows, boxes.next, boxes.order
    nd = dormant.n[0]
    for k in range(nd):
        order[k] = k
    for k in range(1, nd):
        r = order[k]
        code = _pair_code(dormant.i[r], dormant.j[r], nx, nw)
        m = k - 1
        while m >= 0 and _pair_code(dormant.i[order[m]], dormant.j[order[m]], nx, nw) > code:
            order[m + 1] = order[m]
            m -= 1
        order[m + 1] = r
    a, b, c = 0, 0, 0
    while a < old.n[0] or b < nd:
        if b == nd or (
            a < old.n[0]
            and _pair_code(old.i[a], old.j[a], nx, nw)
            < _pair_code(dormant.i[order[b]], dormant.j[order[b]], nx, nw)
        ):
            copy_row(old, a, new, c)
            a += 1
        else:
            copy_row(dormant, order[b], new, c)
            b += 1
        c += 1
    _copy_rows(new, old, c)
    dormant.n[0] = 0


@inner_kernel(_nrt=False)
def box_power(bodies, boxes, out):
    """Add the power [W] of the box contacts' dashpots (``out[POWER_VISCOUS]``) and
    tangential forces (``out[POWER_FRICTION]``) at the full-step velocities
    (contact_rows.rows_power)."""
    rows_power(bodies, boxes.rows, boxes.body, boxes.partner_body, out)


@njit(cache=True, error_model="numpy", _nrt=False)
def box_energies(boxes, out):
    """Add the elastic energies [J] of the box contacts to ``out`` (ENERGY_NAMES vector:
    normal ``k_n delta^2 / 2`` (Hertz: ``2/5 K delta^{5/2}``) to entry 3, tangential
    ``k_t |u|^2 / 2`` to 4, both to the total, 8): the rows, and those put aside (their
    springs keep their energy).  (A scene with spheres is linear: Scene.build.)"""
    hertz = boxes.normal_law[0] == LAW_HERTZ
    _add_energies(rows_elastic_energy(boxes.rows, hertz), out)
    _add_energies(rows_elastic_energy(boxes.dormant, hertz), out)


@inline_kernel()
def _add_energies(elastic, out):
    normal, tangential = elastic
    out[E_ELASTIC_NORMAL] += normal
    out[E_ELASTIC_TANGENTIAL] += tangential
    out[E_TOTAL] += normal + tangential


@inner_kernel(_nrt=False)
def box_contact_forces(boxes, first, second, point, force):
    """The contact forces of the last :func:`box_forces` for the engine's contact-force
    recorder (contact_rows.rows_contact_forces): the rows of the pairs visited, then those
    of the pairs at rest put aside (``boxes.dormant``: held or sleeping boxes, with the
    force they had when put aside, which holds them where they rest).  Shapes are
    numbered spheres first, then boxes.  Writes from row 0 on and returns the number of
    rows."""
    nx = boxes.body.shape[0]
    ns = boxes.partner_body.shape[0] - nx
    n = rows_contact_forces(boxes.rows, ns, ns, first, second, point, force)
    for k in range(n):  # (a sphere partner j = nx + s is shape s)
        if second[k] >= ns + nx:
            second[k] -= ns + nx
    return n + rows_contact_forces(
        boxes.dormant, ns, ns, first[n:], second[n:], point[n:], force[n:]
    )


@inner_kernel(_nrt=False)
def box_peak_force(boxes, peak):
    """Raise ``peak[a, b]`` (a < b bodies, [N]) to the normal force of any box-box or
    box-sphere contact point of the pair (contact_rows.rows_peak_force)."""
    rows_peak_force(boxes.rows, boxes.body, boxes.partner_body, peak)


# --- checkpoints -----------------------------------------------------------------------------
_BOX_ARRAYS = (
    "body", "half", "radius", "material", "normal_law",
    "cand", "n_cand", "cand_start", "rev", "rev_start", "held_at_build",
)  # fmt: skip
"""Arrays of :class:`Boxes` a resumed run depends on; the rest is per-step scratch (the
rows being built, the manifold of one pair, the visited pairs, the change list), written
before it is read."""
_SPHERE_LIST = ("sphere_cand", "n_sphere_cand", "sphere_cand_start")
"""The box-sphere candidate list."""


def box_state(boxes) -> dict[str, np.ndarray]:
    """The box state a run resumes from, as a flat dict of NumPy arrays (copies): the
    bodies' shapes and materials, the normal law, the candidate list, and the contact
    rows of the last step (their used part: feature keys, shear histories, stiffness,
    dashpot, overlap, normal velocity; the box-sphere rows after the others) under
    ``rows.<field>``, the rows of resting pairs put aside (:func:`box_forces`) under
    ``dormant.<field>``."""
    out = {name: np.array(getattr(boxes, name), copy=True) for name in _BOX_ARRAYS + _SPHERE_LIST}
    for group in ("rows", "dormant"):
        rows = getattr(boxes, group)
        n = int(rows.n[0])
        for name, value in rows._asdict().items():
            out[f"{group}.{name}"] = np.array(value if name == "n" else value[:n], copy=True)
    return out


def boxes_from_state(state: dict, sphere_body=()) -> Boxes:
    """The :class:`Boxes` of a :func:`box_state` dict (keys without a prefix), with the
    row capacity of a freshly built scene of the same boxes and spheres of the bodies
    ``sphere_body`` (ns,) (:func:`empty_boxes`).  Every key of :func:`box_state` must be
    there (a state of an older layout is brought to the current one first:
    dem.simulation's ``_upgraded``)."""
    missing = [k for k in box_state(empty_boxes()) if k not in state]
    if missing:
        raise ValueError(f"state is missing 'boxes.{missing[0]}'")
    boxes = empty_boxes(
        state["body"], state["half"], state["radius"], state["material"],
        int(np.asarray(state["normal_law"]).reshape(-1)[0]), sphere_body,
    )  # fmt: skip
    for group in ("rows", "dormant"):
        n = int(np.asarray(state[f"{group}.n"]).reshape(-1)[0])
        rows = getattr(boxes, group)
        if n > rows.i.shape[0]:
            raise ValueError(
                f"state['boxes.{group}.n'] = {n} contact rows, more than the {rows.i.shape[0]}"
                " the scene's boxes hold"
            )
        for name, value in rows._asdict().items():
            if name != "n":
                value[:n] = np.asarray(state[f"{group}.{name}"]).astype(value.dtype)
        rows.n[0] = n
    boxes = boxes._replace(
        **{name: np.array(state[name], np.int64).reshape(-1) for name in _SPHERE_LIST}
    )
    cand = np.array(state["cand"], np.int64)
    boxes.held_at_build[:] = np.asarray(state["held_at_build"], np.uint8)
    return boxes._replace(
        cand=cand,
        n_cand=np.array(state["n_cand"], np.int64).reshape(1),
        cand_start=np.array(state["cand_start"], np.int64),
        rev=np.array(state["rev"], np.int64),
        rev_start=np.array(state["rev_start"], np.int64),
        visit=np.zeros_like(cand),
        n_groups=np.full(1, -1, np.int64),
    )

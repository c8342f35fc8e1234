"""The neighbour list of the contacts of rounded cuboids with spheres (a box and a ball,
a box and the spheres of a clump).

The box-sphere points are found and their law applied with the other points of the
boxes, in one table (boxes.box_forces: the rows of the box pairs, then those of the
box-sphere pairs, boxes._box_sphere_pass).  Pairs within reach are found in two stages,
as for the box pairs: this neighbour list of candidates
(:func:`build_box_sphere_candidates`, built with the spheres' Verlet list), and each
step the bounding test on the candidates.
"""

from __future__ import annotations

import numpy as np

from dominowave.dem.boxes import _reach_of, sphere_centre
from dominowave.dem.compiled import inner_kernel
from dominowave.dem.contact import _candidate_pairs
from dominowave.dem.state import Spheres

__all__ = ["build_box_sphere_candidates"]


# (allocates: compiled with numba's reference counting, as boxes.build_box_candidates)
@inner_kernel(_nrt=True)
def build_box_sphere_candidates(bodies, spheres, boxes, walls, skin):
    """The neighbour list of the box-sphere contacts: every (box, sphere) pair of
    different bodies whose bounding spheres come closer than ``skin`` [m], into
    ``boxes.sphere_cand`` (codes ``box * n_spheres + sphere``, ascending) and
    ``boxes.sphere_cand_start`` (first candidate of each box).  Returns their number, or
    ``-needed`` if ``boxes.sphere_cand`` is too short (then ``n_sphere_cand`` is -1:
    every pair is a candidate until the caller grows it and builds again).

    Bounding spheres: the box's core half-diagonal plus its rounding (the reach of the
    test of boxes._box_sphere_pass), the sphere's radius plus the largest margin,
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
        sphere_centre(bodies, spheres, s, centre)
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

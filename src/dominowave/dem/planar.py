"""Planar scenes: every body moves in one xz plane.

A scene is *planar* (:func:`planar_violation` returns None) when every body has its y
translation and its x and z rotations blocked, with zero y velocity and zero x and z
spin, all bodies lie in one plane ``y = y0`` and every member sphere's centre lies in
it (both to round-off: COPLANAR_ULPS, IN_PLANE_TOLERANCE), and no wall normal has a y
component; a scene with boxes also needs every box's axis 1 along y
(simulation.Simulation.planar).
This is YADE's and the paper's 2D model (DOFs "y rx rz" blocked), e.g. the 2D domino chain.

Then every contact normal, contact point, relative velocity, shear displacement and force
lies in the xz plane, and each body turns about the world y axis only.  The engine
(``settings.planar``: the time loop of a planar kind, engine.time_loop) then places the
spheres at their body's ``y`` exactly (integrate._place_spheres), moves the bodies with
integrate.kick_body_planar / drift_body_planar / advance_body_planar, and maps the
planar kernel of the sphere driver over the Verlet list (contact.compute_forces_planar):
the general driver's source compiled for a planar scene (contact._sphere_driver).

The planar kernel is the general driver (the same per-pair geometry of contact.py and
the same law of a contact point, laws/point.py, without spin about the normal; the zeros
it passes change at most the sign of an exact zero) with the y components passed as
zero and dropped from the results: the components that are exactly zero, and the
round-off that the general kernel carries in them (sphere centres ~1e-17 m off the
plane, from the y row of R(q); the normal's ~1e-15 y component; a spin about the normal
of ~1e-19 rad per step).  That round-off is far below the last bit of every in-plane
quantity: in every scene compared (whole 2D chains with frictionless and frictional
dominoes, damping, floor friction 0.3 and 0.6, with and without the energy ledger; the
scenes of tests/dem/test_dem_planar.py; planes at y0 = 0 and off it) the two kernels
give the same trajectories bit for bit, and differ only in the unused components (force
y, torque x and z) by ~1e-30.  This is an observation, not a theorem: offsets of the
sphere centres near the tolerances above are a tilt of ~1e-13 that the general kernels
feel (a spin about a normal with a 1e-13 y component), so for such a scene the two
differ at round-off, which a chaotic run amplifies -- as any change of the last bit
does.  A contact costs a third fewer loads and operations, and no spin turn of its
shear.
"""

from __future__ import annotations

import numpy as np

from dominowave.dem.integrate import ROT_AXIS, ROT_ISOTROPIC, ROT_NONE

__all__ = ["planar_violation"]

# The bodies count as in one plane if their centres of mass differ in y by at most a few
# units in the last place of y (the mass-weighted centre of spheres at y0 is y0 to
# round-off; any larger offset is a real tilt that the general kernels would feel), and
# a member sphere counts as in its body's plane if its centre is off by at most this
# fraction of its distance from the centre of mass plus its radius (the y row of R(q) of a
# body turned about y is (0, 1, 0) only to round-off, ~1e-15; a single sphere's offset is
# 1 ulp of its y).
COPLANAR_ULPS = 4
IN_PLANE_TOLERANCE = 1e-13


def planar_violation(bodies, spheres, walls) -> str | None:
    """None if the scene is planar (module docstring), else the first reason it is not."""
    if bodies.mass.shape[0] == 0:
        return "the scene has no bodies"
    b = bodies
    unblocked = np.flatnonzero((b.blocked[:, [1, 3, 5]] == 0).any(axis=1))
    if unblocked.size:
        return f"body {unblocked[0]} has y, rx or rz free (blocked = {b.blocked[unblocked[0]]})"
    moving = np.flatnonzero((b.vel[:, 1] != 0) | (b.omega[:, 0] != 0) | (b.omega[:, 2] != 0))
    if moving.size:
        k = moving[0]
        return f"body {k} moves out of the plane (velocity {b.vel[k]}, spin {b.omega[k]})"
    off_axis = (b.rot_mode == ROT_AXIS) & ((b.axis[:, 0] != 0) | (b.axis[:, 2] != 0))
    other = ~np.isin(b.rot_mode, (ROT_AXIS, ROT_ISOTROPIC, ROT_NONE))
    bad = np.flatnonzero(off_axis | other)
    if bad.size:
        return f"body {bad[0]} does not turn about the y axis only"
    slack = COPLANAR_ULPS * np.finfo(float).eps * np.abs(b.pos[:, 1]).max()
    planes = np.flatnonzero(np.abs(b.pos[:, 1] - b.pos[0, 1]) > slack)
    if planes.size:
        return (
            f"body {planes[0]} lies in the plane y = {b.pos[planes[0], 1]}, body 0 in "
            f"y = {b.pos[0, 1]}"
        )
    owner = spheres.body
    offset = np.einsum("sk,sk->s", b.rot[owner, 1, :], spheres.local)
    size = np.linalg.norm(spheres.local, axis=1) + spheres.radius
    off = np.flatnonzero(np.abs(offset) > IN_PLANE_TOLERANCE * size)
    if off.size:
        return f"sphere {off[0]} lies {offset[off[0]]} m out of its body's plane"
    tilted = np.flatnonzero(walls.normal[:, 1] != 0)
    if tilted.size:
        return f"wall {tilted[0]} has a normal with a y component ({walls.normal[tilted[0]]})"
    return None

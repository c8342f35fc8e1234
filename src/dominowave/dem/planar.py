"""Contact kernel for planar scenes: every body moves in one xz plane.

A scene is *planar* (:func:`planar_violation` returns None) when every body has its y
translation and its x and z rotations blocked, with zero y velocity and zero x and z
spin, all bodies lie in one plane ``y = y0`` and every member sphere's centre lies in
it (both to round-off: COPLANAR_ULPS, IN_PLANE_TOLERANCE), and no wall normal has a y
component.
This is YADE's and the paper's 2D model (DOFs "y rx rz" blocked), e.g. the 2D domino chain.

Then every contact normal, contact point, relative velocity, shear displacement and force
lies in the xz plane, and each body turns about the world y axis only.  The engine
(``settings.planar``: the time loop of a planar kind, engine.time_loop) then places the
spheres at their body's ``y`` exactly (integrate._place_spheres), moves the bodies with
integrate.kick_body_planar / drift_body_planar / advance_body_planar, and maps
:func:`compute_forces_planar` over the Verlet list instead of contact.compute_forces.

:func:`compute_forces_planar` is the general contact driver (the same per-pair geometry
of contact.py and the same law of a contact point, laws/point.py, without spin about the
normal; the zeros it passes change at most the sign of an exact zero) with the y
components passed as zero and dropped from the results: the
components that are exactly zero, and the round-off that the general kernel carries in
them (sphere centres ~1e-17 m off the plane, from the y row of R(q); the normal's ~1e-15
y component; a spin about the normal of ~1e-19 rad per step).  That
round-off is far below the last bit of every in-plane quantity: in every scene compared
(whole 2D chains with frictionless and frictional dominoes, damping, floor friction 0.3
and 0.6, with and without the energy ledger; the scenes of tests/dem/test_dem_planar.py;
planes at y0 = 0 and off it) the two kernels give the same trajectories bit for bit, and
differ only in the unused components (force y, torque x and z) by ~1e-30.  This is an
observation, not a theorem: offsets of the sphere centres near the tolerances above are
a tilt of ~1e-13 that the general kernels feel (a spin about a normal with a 1e-13 y
component), so for such a scene the two differ at round-off, which a chaotic run
amplifies -- as any change of the last bit does.  A contact costs a third fewer loads
and operations, and no spin turn of its shear.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from dominowave.dem.contact import (
    END,
    ONSET,
    begin_contact,
    contact_point,
    end_contact,
    idle_pair,
    log_change,
    sphere_sphere,
    sphere_wall,
)
from dominowave.dem.energy import LEDGER_FRICTION, POWER_FRICTION, POWER_VISCOUS
from dominowave.dem.integrate import ROT_AXIS, ROT_ISOTROPIC, ROT_NONE
from dominowave.dem.laws.point import point_law, point_power
from dominowave.dem.laws.tangential import SHEAR_YADE, yade_shear_velocity

__all__ = ["compute_forces_planar", "contact_power_planar", "planar_violation"]

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


@njit(cache=True, error_model="numpy", inline="always")
def _apply_planar(bodies, b, rx, rz, f0, f2, sign):
    """Add ``sign f`` acting at lever arm ``r`` (both in the xz plane) to body b."""
    bodies.force[b, 0] += sign * f0
    bodies.force[b, 2] += sign * f2
    bodies.torque[b, 1] += sign * (rz * f0 - rx * f2)


@njit(cache=True, error_model="numpy", _nrt=False)
def compute_forces_planar(
    bodies, spheres, walls, contacts, dt, ledger, changes, first_step, shear_kinematics
):
    """contact.compute_forces for a planar scene (same arguments, same return value,
    same pair geometry and contact law, both shear kinematics; module docstring): the
    per-pair functions of contact.py with the y components passed as zero."""
    bodies.force[:, :] = 0.0
    bodies.torque[:, :] = 0.0
    pos = spheres.pos
    body_pos, vel, omega = bodies.pos, bodies.vel, bodies.omega
    u = contacts.shear
    n_changes = 0
    for c in range(contacts.n[0]):
        # (unsigned indices: numba adds no negative-index wraparound to every access)
        i = np.uint64(contacts.i[c])
        j = contacts.j[c]
        bi = np.uint64(spheres.body[i])
        Ri = spheres.radius[i]
        active = contacts.active[c]
        wall = j < 0
        if not wall:
            j = np.uint64(j)
            bj = np.uint64(spheres.body[j])
            rsum = Ri + spheres.radius[j]
            near, n0, _, n2, overlap = sphere_sphere(
                pos[i, 0], 0.0, pos[i, 2], pos[j, 0], 0.0, pos[j, 2], rsum, active
            )
        else:
            bj = bi  # (unused)
            w = np.uint64(-j - 1)
            wp, wn = walls.point, walls.normal
            near, n0, _, n2, overlap = sphere_wall(
                pos[i, 0], 0.0, pos[i, 2], Ri, wp[w, 0], 0.0, wp[w, 2],
                wn[w, 0], 0.0, wn[w, 2], active,
            )  # fmt: skip
            rsum = 2.0 * Ri  # (SHEAR_YADE: a wall takes the sphere's radius)
        if not near:
            idle_pair(contacts, c)
            continue
        p0, _, p2 = contact_point(pos[i, 0], 0.0, pos[i, 2], Ri, n0, 0.0, n2, overlap)
        if overlap <= 0.0:
            if not active:  # (d2 < rsum^2, but |d| rounds to rsum: no contact)
                idle_pair(contacts, c)
                continue
            # an active contact opened in the last drift (its force lies in the plane;
            # the lever's y component only enters the torque's x and z, which nothing reads)
            ledger[LEDGER_FRICTION] += end_contact(
                bodies, contacts, c, bi, bj, wall, n0, 0.0, n2, overlap, dt, p0, pos[i, 1], p2
            )
            n_changes = log_change(changes, n_changes, c, END)
            continue
        new_contact = not active
        if new_contact:
            begin_contact(contacts, c)
            n_changes = log_change(changes, n_changes, c, ONSET)
        # relative velocity of the contact point, j minus i (a wall is fixed);
        # v + omega x r with omega = (0, w, 0): (v_x + w r_z, v_z - w r_x)
        ri0, ri2 = p0 - body_pos[bi, 0], p2 - body_pos[bi, 2]
        wi = omega[bi, 1]
        dv0, dv2 = -(vel[bi, 0] + wi * ri2), -(vel[bi, 2] - wi * ri0)
        rj0 = rj2 = 0.0
        if not wall:
            rj0, rj2 = p0 - body_pos[bj, 0], p2 - body_pos[bj, 2]
            wj = omega[bj, 1]
            dv0 += vel[bj, 0] + wj * rj2
            dv2 += vel[bj, 2] - wj * rj0
        # the relative velocity that drives the shear (laws/tangential.py); sphere centres
        # move with (v_x + w r_z, v_z - w r_x), r = centre - centre of mass
        s0, s2 = dv0, dv2
        if shear_kinematics == SHEAR_YADE:
            ci0 = vel[bi, 0] + wi * (pos[i, 2] - body_pos[bi, 2])
            ci2 = vel[bi, 2] - wi * (pos[i, 0] - body_pos[bi, 0])
            a1 = Ri * wi
            cj0 = cj2 = 0.0
            if not wall:
                js = np.uint64(contacts.j[c])  # (j is typed as a float after the branches)
                wj = omega[bj, 1]
                cj0 = vel[bj, 0] + wj * (pos[js, 2] - body_pos[bj, 2])
                cj2 = vel[bj, 2] - wj * (pos[js, 0] - body_pos[bj, 0])
                a1 += spheres.radius[js] * wj
            s0, _, s2 = yade_shear_velocity(
                cj0 - ci0, 0.0, cj2 - ci2, 0.0, a1, 0.0, n0, 0.0, n2, rsum, overlap
            )
        # the contact point's law with the y components zero (no spin about the normal)
        fn, fn_viscous, vn, u0, _, u2, released, f0, _, f2 = point_law(
            overlap, n0, 0.0, n2, dv0, 0.0, dv2, s0, 0.0, s2, 0.0, u[c, 0], 0.0, u[c, 2],
            contacts.vn[c], new_contact, contacts.kn[c], contacts.kt[c], contacts.mu[c],
            contacts.cn[c], dt, first_step, False,
        )  # fmt: skip
        u[c, 0], u[c, 1], u[c, 2] = u0, 0.0, u2
        contacts.vn[c] = vn
        contacts.overlap[c] = overlap
        contacts.fn[c] = fn
        contacts.fn_viscous[c] = fn_viscous
        # friction ledger, part 1: minus the change of the energy stored in the spring
        ledger[LEDGER_FRICTION] += released
        if not wall:
            _apply_planar(bodies, bj, rj0, rj2, f0, f2, 1.0)
        _apply_planar(bodies, bi, ri0, ri2, f0, f2, -1.0)
    return n_changes


@njit(cache=True, error_model="numpy", _nrt=False)
def contact_power_planar(bodies, spheres, walls, contacts, out):
    """contact.contact_power for a planar scene (same arguments and outputs), without the y
    components: the same sums to the bit (``v_y`` of every contact point and the shear's
    ``u_y`` are exactly zero in a planar run)."""
    pos = spheres.pos
    body_pos, vel, omega = bodies.pos, bodies.vel_full, bodies.omega_full
    u = contacts.shear
    p_viscous = 0.0
    p_friction = 0.0
    for c in range(contacts.n[0]):
        fd = contacts.fn_viscous[c]
        if fd == 0.0 and (not contacts.active[c] or u[c, 0] == u[c, 2] == 0.0):
            continue  # (ended contacts have zero shear)
        i = contacts.i[c]
        j = contacts.j[c]
        bi = spheres.body[i]
        Ri = spheres.radius[i]
        if j >= 0:
            _, n0, _, n2, _ = sphere_sphere(
                pos[i, 0], 0.0, pos[i, 2], pos[j, 0], 0.0, pos[j, 2], 0.0, True
            )
        else:
            wn = walls.normal
            _, n0, _, n2, _ = sphere_wall(
                pos[i, 0], 0.0, pos[i, 2], Ri, 0.0, 0.0, 0.0,
                wn[-j - 1, 0], 0.0, wn[-j - 1, 2], True,
            )  # fmt: skip
        p0, _, p2 = contact_point(pos[i, 0], 0.0, pos[i, 2], Ri, n0, 0.0, n2, contacts.overlap[c])
        ri0, ri2 = p0 - body_pos[bi, 0], p2 - body_pos[bi, 2]
        dv0 = -(vel[bi, 0] + omega[bi, 1] * ri2)
        dv2 = -(vel[bi, 2] - omega[bi, 1] * ri0)
        if j >= 0:
            bj = spheres.body[j]
            rj0, rj2 = p0 - body_pos[bj, 0], p2 - body_pos[bj, 2]
            dv0 += vel[bj, 0] + omega[bj, 1] * rj2
            dv2 += vel[bj, 2] - omega[bj, 1] * rj0
        viscous, friction = point_power(
            fd, n0, 0.0, n2, dv0, 0.0, dv2, contacts.kt[c], u[c, 0], 0.0, u[c, 2]
        )
        p_viscous += viscous
        p_friction += friction
    out[POWER_VISCOUS] = p_viscous
    out[POWER_FRICTION] = p_friction

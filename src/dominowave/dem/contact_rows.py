"""The contact rows: one record of a contact point for every driver, and its bookkeeping.

Every contact driver writes its contact points as rows of the same fields (MuJoCo's one
contact record): the pair ``i, j`` (``j < 0``: the wall ``-(j + 1)``), the ``point`` [m]
and the unit ``normal`` from i to j, the multiplicity ``mult`` (a planar box row stands
for two points of the 3D body), the state of the law (``overlap`` [m], ``fn`` and its
dashpot part ``fn_viscous`` [N], the shear displacement ``shear`` [m]) and the constants
of the pair (``kn``, ``kt``, ...): the one record ``state.Contacts``.  The tables are

* the spheres' Verlet list (contact.compute_forces): one row per listed pair, a contact
  point while its overlap is positive (an idle pair's overlap is zero or the gap at
  which it ended);
* the rows of the boxes (``Boxes.rows``, boxes.box_forces): one row per touching point
  of a box with a box, a wall or a sphere (the box-sphere rows after the others, their
  partner ``j = n_boxes + sphere``), with the feature key of the point (shapes.cuboid).

A row touches while ``overlap > 0``.  The power of the contact forces (the energy
ledger), their elastic energy, the recorded contact forces and the peak forces of the
body pairs are each computed here once, for every table (YADE's and MuJoCo's loops over
one interaction container).  ``body_i``, ``body_j`` map a row's ``i`` and ``j >= 0`` to
their bodies (spheres.body, boxes.body).  Each driver lists the contacts that started or
ended in its step in one layout (:func:`log_change`, with the time since the event,
:func:`event_lag`), which the engine books (engine._bookkeep).
"""

from __future__ import annotations

from dominowave.dem.compiled import inline_kernel
from dominowave.dem.laws.point import point_energy, point_power

__all__ = [
    "END",
    "ONSET",
    "POWER_FRICTION",
    "POWER_VISCOUS",
    "copy_row",
    "event_lag",
    "lever_arm",
    "log_change",
    "point_velocity",
    "relative_velocity",
    "rows_contact_forces",
    "rows_elastic_energy",
    "rows_peak_force",
    "rows_power",
]

# entries of the (2,) power vector of rows_power [W]
POWER_VISCOUS = 0
POWER_FRICTION = 1

# the kind of a contact change (log_change)
ONSET = 1
END = 0


@inline_kernel(python_entry=True)
def event_lag(depth, speed, dt, first_step):
    """Time [s] before the end of the last drift ``[t - dt, t]`` at which a contact started
    or ended, the overlap taken linear over the drift: an onset seen with overlap
    ``depth`` [m] and approach speed ``speed`` [m/s] happened ``depth / speed`` before
    ``t``, an end seen with gap ``|depth|`` and separation speed ``speed`` as long before.
    0 for the initial configuration (``first_step``) and without approach or separation
    (``speed <= 0``), at most dt."""
    if first_step or speed <= 0.0:
        return 0.0
    if abs(depth) >= speed * dt:
        return dt
    return abs(depth) / speed


@inline_kernel()
def log_change(changes, lag, n, bi, bj, kind, before):
    """Row n of a driver's list of contact changes: body ``bi`` and body ``bj`` (or the
    wall ``-(bj + 1)``) started (``kind`` ONSET) or ended (END) a contact a time
    ``before`` [s] (:func:`event_lag`) before this step's time; ``changes`` (K, 3) int64,
    ``lag`` (K,).  Returns n + 1."""
    if n == changes.shape[0]:
        raise RuntimeError("contact changes full")
    changes[n, 0] = bi
    changes[n, 1] = bj
    changes[n, 2] = kind
    lag[n] = before
    return n + 1


@inline_kernel()
def copy_row(src, s, dst, c):
    """Row s of the table ``src`` into row c of ``dst`` (state.Contacts, every field): a
    contact moved to another row, or put aside, keeps its whole history."""
    dst.i[c] = src.i[s]
    dst.j[c] = src.j[s]
    dst.key[c] = src.key[s]
    dst.mult[c] = src.mult[s]
    dst.overlap[c] = src.overlap[s]
    dst.vn[c] = src.vn[s]
    dst.fn[c] = src.fn[s]
    dst.fn_viscous[c] = src.fn_viscous[s]
    dst.kn[c] = src.kn[s]
    dst.kt[c] = src.kt[s]
    dst.mu[c] = src.mu[s]
    dst.cn[c] = src.cn[s]
    for d in range(3):
        dst.shear[c, d] = src.shear[s, d]
        dst.point[c, d] = src.point[s, d]
        dst.normal[c, d] = src.normal[s, d]


@inline_kernel()
def lever_arm(pos, b, p0, p1, p2):
    """Lever arm ``p - x_b`` [m] of the point ``p`` about the centre of mass of body b
    (``pos`` (nb, 3) the body positions)."""
    return p0 - pos[b, 0], p1 - pos[b, 1], p2 - pos[b, 2]


@inline_kernel()
def point_velocity(vel, omega, b, rx, ry, rz):
    """Velocity ``v + omega x r`` [m/s] of the material point at lever arm ``r`` of body b.

    ``vel``/``omega`` (nb, 3) are the body velocities to use: the half-step ones for the
    contact law, the full-step ones for the energy ledger.
    """
    return (
        vel[b, 0] + omega[b, 1] * rz - omega[b, 2] * ry,
        vel[b, 1] + omega[b, 2] * rx - omega[b, 0] * rz,
        vel[b, 2] + omega[b, 0] * ry - omega[b, 1] * rx,
    )


@inline_kernel()
def relative_velocity(bodies, vel, omega, bi, bj, wall, p):
    """Velocity [m/s] of the material point p (3,) [m] of body j minus that of body i (a
    wall is fixed), with the body velocities ``vel``, ``omega`` (nb, 3): the half-step ones
    for the contact law, the full-step ones for the energy ledger."""
    rx, ry, rz = lever_arm(bodies.pos, bi, p[0], p[1], p[2])
    vi0, vi1, vi2 = point_velocity(vel, omega, bi, rx, ry, rz)
    v0, v1, v2 = -vi0, -vi1, -vi2
    if not wall:
        rx, ry, rz = lever_arm(bodies.pos, bj, p[0], p[1], p[2])
        vj0, vj1, vj2 = point_velocity(vel, omega, bj, rx, ry, rz)
        v0 += vj0
        v1 += vj1
        v2 += vj2
    return v0, v1, v2


@inline_kernel()
def rows_power(bodies, rows, body_i, body_j, out):
    """Add the power [W] at t_n of the dashpot forces (``out[POWER_VISCOUS]``) and of the
    tangential forces (``out[POWER_FRICTION]``) of the rows: ``mult F_d v_n`` and ``-mult
    k_t u . dv`` (laws.point.point_power) with the full-step relative velocity of the
    contact point, the velocity in which the kinetic-energy change of velocity Verlet is
    exact to O(dt^3) per step.  The caller integrates them with the trapezoidal rule; the
    friction dissipation is minus the tangential work minus the change of the energy stored
    in the springs (booked by the drivers), which closes the balance to O(dt^2) with
    rotating bodies and turning contact frames as well.

    ``F_d`` is the row's ``fn_viscous``, including the dashpot part of the end impulse of a
    sphere pair that ended in the last drift (laws.linear.end_impulse; its row keeps the
    point and normal of this step).  The elastic onset and end corrections are part of the
    elastic force and are not booked."""
    for c in range(rows.n[0]):
        fd = rows.fn_viscous[c]
        u = rows.shear[c]
        if fd == 0.0 and (rows.overlap[c] <= 0.0 or (u[0] == 0.0 and u[1] == 0.0 and u[2] == 0.0)):
            continue  # (no power; an idle row, as most listed sphere pairs, has no shear)
        wall = rows.j[c] < 0
        bi = body_i[rows.i[c]]
        bj = bi if wall else body_j[rows.j[c]]
        dv0, dv1, dv2 = relative_velocity(
            bodies, bodies.vel_full, bodies.omega_full, bi, bj, wall, rows.point[c]
        )
        n = rows.normal[c]
        viscous, friction = point_power(
            fd, n[0], n[1], n[2], dv0, dv1, dv2, rows.kt[c], u[0], u[1], u[2]
        )
        # (mult 1 or 2: exact scaling, as in rows_elastic_energy)
        out[POWER_VISCOUS] += rows.mult[c] * viscous
        out[POWER_FRICTION] += rows.mult[c] * friction


@inline_kernel()
def rows_elastic_energy(rows, hertz):
    """The elastic energies [J] of the touching rows: normal ``k_n delta^2 / 2`` (``hertz``:
    ``2/5 K delta^{5/2}``) and tangential ``k_t |u|^2 / 2``, each row ``mult`` times its
    point's (laws.point.point_energy).  Returns ``(normal, tangential)``."""
    en = 0.0
    es = 0.0
    # (mult is 1 or 2: scaling by it commutes with the rounding of the point's products,
    # so the sums are those of the rows' own products)
    for c in range(rows.n[0]):
        if rows.overlap[c] <= 0.0:
            continue
        u = rows.shear[c]
        normal, tangential = point_energy(
            rows.kn[c], rows.kt[c], rows.overlap[c], u[0], u[1], u[2], hertz
        )
        en += rows.mult[c] * normal
        es += rows.mult[c] * tangential
    return en, es


@inline_kernel()
def rows_contact_forces(rows, offset_i, offset_j, first, second, point, force):
    """The touching rows for the contact-force recorder, written from row 0 on; returns
    their number.

    Shapes are numbered across the tables: row partner i is shape ``offset_i + i``, a
    partner ``j >= 0`` shape ``offset_j + j`` (spheres first, then boxes).  A pair row:
    ``first``, ``second`` the two shapes, ``force`` the force on ``second``; a wall row:
    ``first = -(wall + 1)``, ``second`` the shape i, ``force`` the force on it.  ``force``
    (3,) [N] is the force as applied in the last kick, ``mult (F_n n - k_t u)`` (a planar
    row stands for ``mult`` points of the 3D body: their sum), ``point`` (3,) [m] the
    contact point.  The end impulse of a point that opened in the last drift is not a row.
    Arrays: ``first, second`` (K,) int64, ``point, force`` (K, 3), K >= the touching rows.
    """
    k = 0
    for c in range(rows.n[0]):
        if rows.overlap[c] <= 0.0:
            continue
        j = rows.j[c]
        if j >= 0:
            first[k] = offset_i + rows.i[c]
            second[k] = offset_j + j
            sign = 1.0
        else:
            first[k] = j
            second[k] = offset_i + rows.i[c]
            sign = -1.0
        n = rows.normal[c]
        u = rows.shear[c]
        fn, kt, m = rows.fn[c], rows.kt[c], rows.mult[c]
        for d in range(3):
            point[k, d] = rows.point[c, d]
            force[k, d] = sign * m * (fn * n[d] - kt * u[d])
        k += 1
    return k


@inline_kernel()
def rows_peak_force(rows, body_i, body_j, peak):
    """Raise ``peak[a, b]`` (bodies a < b, [N]) to the normal force of every touching row
    of the pair (walls left out)."""
    for c in range(rows.n[0]):
        j = rows.j[c]
        if j < 0 or rows.overlap[c] <= 0.0:
            continue
        bi = body_i[rows.i[c]]
        bj = body_j[j]
        a = min(bi, bj)
        b = max(bi, bj)
        if rows.fn[c] > peak[a, b]:
            peak[a, b] = rows.fn[c]

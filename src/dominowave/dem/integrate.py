"""Time integration of rigid bodies: leapfrog / velocity Verlet with local damping.

Step ``n -> n+1`` (forces ``F_n`` already computed at positions ``x_n``):

1. kick   ``v_{n+1/2} = v_{n-1/2} + dt a_n``  (``L`` likewise for rotations), with YADE's
   local (Cundall non-viscous) damping applied to ``a_n`` component-wise;
2. drift  ``x_{n+1} = x_n + dt v_{n+1/2}`` and the orientation update.

This is YADE's NewtonIntegrator leapfrog (velocities at half steps).  The full-step
velocity ``v_n = (v_{n-1/2} + v_{n+1/2}) / 2`` is stored for recorders and energies (not
in the fused steps of planar scenes, where nothing reads it: :func:`advance_body_planar`).

Rotations (``rot_mode`` of a body):

* 0 isotropic (spheres): ``omega += dt T / I``; the quaternion is turned by the exact
  rotation ``exp(omega dt)``; any blocked rotation component is simply never changed.
* 1 free aspherical body: angular momentum ``L`` (world) is kicked by the torque; the
  free rotation for ``dt`` is the symmetric splitting of Dullweber, Leimkuhler & McLachlan
  (J. Chem. Phys. 107, 5840 (1997)) into exact rotations about the principal axes
  1(dt/2) 2(dt/2) 3(dt) 2(dt/2) 1(dt/2) — the quaternion form of NO_SQUISH (Miller et al.,
  J. Chem. Phys. 116, 8649 (2002)).  It is symplectic and time-reversible, conserves |L|
  exactly and the energy of a free asymmetric top without drift, which YADE's
  Fincham-type predictor (NewtonIntegrator::leapfrogAsphericalRotate) does not guarantee.
* 2 rotation about one fixed world axis ``e`` (two rotations blocked, e.g. the planar xz
  model): ``omega = w e``, ``dw/dt = T.e / I_e`` with ``I_e`` the constant moment of inertia
  about ``e`` through the COM; exact for a hinge-free planar rigid body.
* 3 no rotation.

Local damping (YADE NewtonIntegrator, ``cundallDamp2nd``; Cundall 1987; see the YADE
documentation "Numerical damping"): each acceleration component becomes
``a_i (1 - lambda sign(a_i (v_i + dt a_i / 2)))`` with the half-step velocity ``v_i``.
With ``damp_gravity`` (default, YADE 2023.02a) gravity is part of ``a``; otherwise only the
contact acceleration is damped and gravity added afterwards.  Aspherical free bodies use
``T_i (1 - lambda sign(T_i omega_i))`` (YADE's ``cundallDamp1st`` for aspherical bodies).
The power of the damping forces ``(F_damped - F) . v_n`` is returned and integrated
by the trapezoidal rule, which matches the velocity-Verlet kinetic energy exactly for
constant forces (so the energy ledger closes to O(dt^2), without an O(dt) offset).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from dominowave.dem.compiled import inline_kernel, inner_kernel

__all__ = [
    "advance_body_planar",
    "check_blocked_spin",
    "drift",
    "drift_body",
    "drift_body_planar",
    "kick",
    "kick_body",
    "kick_body_planar",
    "update_listed_sphere_positions",
    "update_sphere_positions",
]

ROT_ISOTROPIC = 0
ROT_FREE = 1
ROT_AXIS = 2
ROT_NONE = 3


def check_blocked_spin(body, omega, mode, axis):
    """ValueError if an aspherical clump is given a spin about a blocked rotation axis.

    Spheres keep a blocked component (YADE: a blocked DOF keeps its velocity); a planar
    clump (``ROT_AXIS``) turns only about ``axis``, a clump with every rotation blocked
    (``ROT_NONE``) not at all, so silently dropping the rest would change the input.
    """
    if mode == ROT_AXIS:
        stray = omega - axis * (omega @ axis)
    elif mode == ROT_NONE:
        stray = omega
    else:
        return
    if np.any(np.abs(stray) > 1e-12 * max(1.0, float(np.abs(omega).max()))):
        raise ValueError(
            f"angular_velocity = {omega.tolist()} rad/s of body {body} turns about a blocked "
            "axis; an aspherical clump with blocked rotations can only turn about its free "
            "axis (valid: components about blocked axes = 0)"
        )


@inline_kernel()
def _sign(x):
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return 0.0


@inline_kernel()
def damped(a, v, dt, damping):
    """YADE's local damping of one acceleration component: a (1 - lambda sign(a (v + dt a/2)))."""
    return a * (1.0 - damping * _sign(a * (v + 0.5 * dt * a)))


@inline_kernel()
def _store_rows_xz(rot, b, w, x, y, z):
    """Rows x and z of :func:`_store_matrix` (all that the planar sphere placement reads)."""
    rot[b, 0, 0] = 1.0 - 2.0 * (y * y + z * z)
    rot[b, 0, 1] = 2.0 * (x * y - w * z)
    rot[b, 0, 2] = 2.0 * (x * z + w * y)
    rot[b, 2, 0] = 2.0 * (x * z - w * y)
    rot[b, 2, 1] = 2.0 * (y * z + w * x)
    rot[b, 2, 2] = 1.0 - 2.0 * (x * x + y * y)


@inline_kernel()
def _store_matrix(rot, b, w, x, y, z):
    """``rot[b]`` = the rotation matrix of the unit quaternion ``(w, x, y, z)`` (body ->
    world; the kernels index rows of the (nb, 3, 3) array, they take no row views)."""
    _store_rows_xz(rot, b, w, x, y, z)
    rot[b, 1, 0] = 2.0 * (x * y + w * z)
    rot[b, 1, 1] = 1.0 - 2.0 * (x * x + z * z)
    rot[b, 1, 2] = 2.0 * (y * z - w * x)


# Below this half angle [rad] a turn takes cos x and sin(x)/x from their Taylor series to
# x^4 (the first omitted terms, x^6/720 and x^6/5040, are < 1.4e-21 relative): no sqrt,
# sin, cos or division.  The paper chain (k/k* = 1e4) turns a body by |omega dt| <= 2e-3
# per step (half angle <= 1e-3); larger turns (softer contacts, longer steps) take the C
# library's sin and cos -- only the speed differs.
SMALL_HALF_ANGLE = 1e-3


@inline_kernel()
def _cos_sinc(x2):
    """``(cos x, sin(x) / x)`` from ``x^2`` for ``x^2 < SMALL_HALF_ANGLE^2`` (Taylor series;
    products with reciprocals, which LLVM folds, instead of divisions)."""
    cos_x = 1.0 - x2 * (0.5 - x2 * (1.0 / 24.0))
    sinc_x = 1.0 - x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0))
    return cos_x, sinc_x


@inline_kernel()
def _half_turn(w2, dt):
    """``(cos x, sin(x) / |omega|)`` of the half angle ``x = |omega| dt / 2`` of a turn at
    angular speed ``|omega| = sqrt(w2)`` [rad/s] over ``dt`` [s] (Taylor below
    SMALL_HALF_ANGLE, the C library above)."""
    x2 = 0.25 * dt * dt * w2
    if x2 < SMALL_HALF_ANGLE * SMALL_HALF_ANGLE:
        cos_x, sinc = _cos_sinc(x2)
        return cos_x, 0.5 * dt * sinc
    wn = math.sqrt(w2)
    return math.cos(0.5 * wn * dt), math.sin(0.5 * wn * dt) / wn


@inline_kernel(python_entry=True)
def _turn_world(q, b, wx, wy, wz, dt):
    """q[b] <- exp(omega dt) * q[b]: rotate body b by the world-frame angle vector omega dt.

    The rotation quaternion is ``(cos x, sin(x)/|omega| omega)`` with ``x = |omega| dt / 2``.
    """
    w2 = wx * wx + wy * wy + wz * wz
    if w2 == 0.0:
        return
    a0, s = _half_turn(w2, dt)
    a1, a2, a3 = wx * s, wy * s, wz * s
    q0, q1, q2, q3 = q[b, 0], q[b, 1], q[b, 2], q[b, 3]
    q[b, 0] = a0 * q0 - a1 * q1 - a2 * q2 - a3 * q3
    q[b, 1] = a0 * q1 + a1 * q0 + a2 * q3 - a3 * q2
    q[b, 2] = a0 * q2 - a1 * q3 + a2 * q0 + a3 * q1
    q[b, 3] = a0 * q3 + a1 * q2 - a2 * q1 + a3 * q0


# A product of unit quaternions has unit norm to round-off (~1e-16 per turn, a random
# walk).  The orientation is rescaled when its squared norm is off by more than this: the
# rotation matrix then deviates from orthogonal by < 4e-14, which moves a sphere 5 cm from
# the centre of mass by ~1e-15 m, while the test stays off the critical path of a step.
QUAT_NORM_TOLERANCE = 1e-14


@inline_kernel(python_entry=True)
def _normalise(q, b):
    """Rescale q[b] to unit norm if ``| |q|^2 - 1 | > QUAT_NORM_TOLERANCE``."""
    q0, q1, q2, q3 = q[b, 0], q[b, 1], q[b, 2], q[b, 3]
    n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
    if abs(n2 - 1.0) > QUAT_NORM_TOLERANCE:
        scale = 1.0 / math.sqrt(n2)
        for k in range(4):
            q[b, k] *= scale


@inline_kernel(python_entry=True)
def _turn_body_axis(q, b, L0, L1, L2, k, phi):
    """Free rotation of body b about principal axis k by angle phi:
    q[b] <- q[b] * (cos phi/2, sin phi/2 e_k).  Returns the body components
    ``(L0, L1, L2)`` of the (fixed) world angular momentum, turned by -phi."""
    half = 0.5 * phi
    if half * half < SMALL_HALF_ANGLE * SMALL_HALF_ANGLE:
        c, sinc = _cos_sinc(half * half)
        s = half * sinc
    else:
        c = math.cos(half)
        s = math.sin(half)
    # the full angle from the half angle: cos phi = c^2 - s^2, sin phi = 2 s c
    cp = c * c - s * s
    sp = 2.0 * s * c
    q0, q1, q2, q3 = q[b, 0], q[b, 1], q[b, 2], q[b, 3]
    if k == 0:
        q[b, 0] = q0 * c - q1 * s
        q[b, 1] = q1 * c + q0 * s
        q[b, 2] = q2 * c + q3 * s
        q[b, 3] = q3 * c - q2 * s
        return L0, cp * L1 + sp * L2, -sp * L1 + cp * L2
    if k == 1:
        q[b, 0] = q0 * c - q2 * s
        q[b, 1] = q1 * c - q3 * s
        q[b, 2] = q2 * c + q0 * s
        q[b, 3] = q3 * c + q1 * s
        return -sp * L2 + cp * L0, L1, cp * L2 + sp * L0
    q[b, 0] = q0 * c - q3 * s
    q[b, 1] = q1 * c + q2 * s
    q[b, 2] = q2 * c - q1 * s
    q[b, 3] = q3 * c + q0 * s
    return cp * L0 + sp * L1, -sp * L0 + cp * L1, L2


@inline_kernel()
def _omega_from_angmom(rot, inertia, L, out, b):
    """out[b] = R I^-1 R^T L[b] (world frame) for body b."""
    for k in range(3):
        lb = (rot[b, 0, k] * L[b, 0] + rot[b, 1, k] * L[b, 1] + rot[b, 2, k] * L[b, 2]) / inertia[
            b, k
        ]
        if k == 0:
            out[b, 0] = rot[b, 0, 0] * lb
            out[b, 1] = rot[b, 1, 0] * lb
            out[b, 2] = rot[b, 2, 0] * lb
        else:
            out[b, 0] += rot[b, 0, k] * lb
            out[b, 1] += rot[b, 1, k] * lb
            out[b, 2] += rot[b, 2, k] * lb


@inline_kernel()
def _kick_length(bodies, b, dt):
    """The time [s] over which body b is kicked: ``dt``, or ``dt/2`` for a fresh body (the
    half kick of a velocity-Verlet start; the flag is cleared)."""
    if bodies.fresh[b]:
        bodies.fresh[b] = 0
        return 0.5 * dt
    return dt


@inline_kernel()
def _kick_translation(bodies, b, k, h, inv_m, gravity, dt, damping, damp_gravity):
    """Kick of the velocity component k of body b by ``h`` (a blocked component keeps its
    velocity); returns the power of its local damping [W]."""
    v = bodies.vel[b, k]
    if bodies.blocked[b, k]:
        bodies.vel_full[b, k] = v
        return 0.0
    a_contact = bodies.force[b, k] * inv_m
    a, a_free = _accelerate(a_contact, gravity[k], v, dt, damping, damp_gravity)
    v_new = v + h * a
    bodies.vel[b, k] = v_new
    bodies.vel_full[b, k] = v_new - 0.5 * dt * a
    return bodies.mass[b] * (a - a_free) * bodies.vel_full[b, k]


@inline_kernel()
def kick_body(bodies, b, gravity, dt, damping, damp_gravity):
    """Kick of body b (see :func:`kick`); returns the power of its local damping [W]."""
    power = 0.0
    if bodies.held[b]:
        return power
    h = _kick_length(bodies, b, dt)
    inv_m = 1.0 / bodies.mass[b]  # (one division per body, not per component)
    for k in range(3):
        power += _kick_translation(bodies, b, k, h, inv_m, gravity, dt, damping, damp_gravity)
    mode = bodies.rot_mode[b]
    if mode == ROT_ISOTROPIC:
        inertia = bodies.inertia[b, 0]
        for k in range(3):
            w = bodies.omega[b, k]
            if bodies.blocked[b, 3 + k]:
                bodies.omega_full[b, k] = w
                bodies.angmom_full[b, k] = inertia * w
                continue
            alpha = bodies.torque[b, k] / inertia
            alpha_d = damped(alpha, w, dt, damping) if damping != 0.0 else alpha
            w_new = w + h * alpha_d
            w_full = w_new - 0.5 * dt * alpha_d
            bodies.omega[b, k] = w_new
            bodies.angmom[b, k] = inertia * w_new
            bodies.omega_full[b, k] = w_full
            bodies.angmom_full[b, k] = inertia * w_full
            power += inertia * (alpha_d - alpha) * w_full
    elif mode == ROT_AXIS:
        inertia = bodies.axis_inertia[b]
        e0, e1, e2 = bodies.axis[b, 0], bodies.axis[b, 1], bodies.axis[b, 2]
        w = bodies.omega[b, 0] * e0 + bodies.omega[b, 1] * e1 + bodies.omega[b, 2] * e2
        torque = bodies.torque[b, 0] * e0 + bodies.torque[b, 1] * e1
        # (the reciprocal is computed in parallel with the torque, off the critical path)
        alpha = (torque + bodies.torque[b, 2] * e2) * (1.0 / inertia)
        alpha_d = damped(alpha, w, dt, damping) if damping != 0.0 else alpha
        w_new = w + h * alpha_d
        w_full = w_new - 0.5 * dt * alpha_d
        for k in range(3):
            e = bodies.axis[b, k]
            bodies.omega[b, k] = w_new * e
            bodies.angmom[b, k] = inertia * w_new * e
            bodies.omega_full[b, k] = w_full * e
            bodies.angmom_full[b, k] = inertia * w_full * e
        power += inertia * (alpha_d - alpha) * w_full
    elif mode == ROT_FREE:
        d0 = d1 = d2 = 0.0  # damping torque
        for k in range(3):
            t = bodies.torque[b, k]
            w = bodies.omega[b, k]
            t_d = t * (1.0 - damping * _sign(t * w)) if damping != 0.0 else t
            L_new = bodies.angmom[b, k] + h * t_d
            bodies.angmom[b, k] = L_new
            bodies.angmom_full[b, k] = L_new - 0.5 * dt * t_d
            if k == 0:
                d0 = t_d - t
            elif k == 1:
                d1 = t_d - t
            else:
                d2 = t_d - t
        # full-step omega at the current orientation, for recorders and energies
        _omega_from_angmom(bodies.rot, bodies.inertia, bodies.angmom_full, bodies.omega_full, b)
        power += d0 * bodies.omega_full[b, 0]
        power += d1 * bodies.omega_full[b, 1]
        power += d2 * bodies.omega_full[b, 2]
    return power


@inline_kernel()
def _accelerate(a_contact, g, v, dt, damping, damp_gravity):
    """One component's acceleration ``(a, a_free)`` [m/s^2] from the contact part and
    gravity ``g``, with the local damping of :func:`damped` (``damp_gravity``: of both)."""
    a_free = a_contact + g
    if damping == 0.0:
        return a_free, a_free
    if damp_gravity:
        return damped(a_free, v, dt, damping), a_free
    return damped(a_contact, v, dt, damping) + g, a_free


@inline_kernel()
def _spin_acceleration(bodies, b):
    """``(d omega_y / dt, I_y)`` of a body of a planar scene (its torque about e_y)."""
    if bodies.rot_mode[b] == ROT_AXIS:
        inertia = bodies.axis_inertia[b]
        return bodies.torque[b, 1] * (1.0 / inertia), inertia
    inertia = bodies.inertia[b, 0]  # ROT_ISOTROPIC
    return bodies.torque[b, 1] / inertia, inertia


@inline_kernel()
def kick_body_planar(bodies, b, gravity, dt, damping, damp_gravity):
    """:func:`kick_body` of a body of a planar scene (dem/planar.py: y, rx, rz blocked,
    turning about e_y only), without the y, rx and rz components that stay zero: the
    same arithmetic on the other components, so the same results to the bit (a term that
    is exactly zero changes no sum; tests/dem/test_dem_planar.py)."""
    power = 0.0
    if bodies.held[b]:
        return power
    h = _kick_length(bodies, b, dt)
    inv_m = 1.0 / bodies.mass[b]
    for k in (0, 2):
        power += _kick_translation(bodies, b, k, h, inv_m, gravity, dt, damping, damp_gravity)
    if bodies.rot_mode[b] == ROT_NONE or bodies.blocked[b, 4]:
        return power
    w = bodies.omega[b, 1]
    alpha, inertia = _spin_acceleration(bodies, b)
    alpha_d = damped(alpha, w, dt, damping) if damping != 0.0 else alpha
    w_new = w + h * alpha_d
    w_full = w_new - 0.5 * dt * alpha_d
    bodies.omega[b, 1] = w_new
    bodies.angmom[b, 1] = inertia * w_new
    bodies.omega_full[b, 1] = w_full
    bodies.angmom_full[b, 1] = inertia * w_full
    return power + inertia * (alpha_d - alpha) * w_full


@inner_kernel(_nrt=False)
def kick_general(bodies, gravity, dt, damping, damp_gravity, first, stop):
    """Half-step velocities v_{n-1/2} -> v_{n+1/2} from the current forces (module doc),
    of the bodies ``first .. stop - 1``, a range that holds every body not held (a held
    body is not kicked: the range only spares the loop the long runs of held dominoes
    before and after the front of a chain).

    A body flagged ``fresh`` (new, or given a velocity) holds the full-step
    velocity v_n instead, and gets the half kick ``v_{n+1/2} = v_n + dt/2 a_n`` of the
    velocity-Verlet start.  Returns the power of the local damping forces at t_n [W]
    (negative), booked by the caller with the trapezoidal rule.
    """
    power = 0.0
    for b in range(first, stop):
        power += kick_body(bodies, b, gravity, dt, damping, damp_gravity)
    return power


@inner_kernel(_nrt=False)
def kick_planar(bodies, gravity, dt, damping, damp_gravity, first, stop):
    """:func:`kick_general` for a planar scene (dem/planar.py): the same results, fewer
    operations (:func:`kick_body_planar`)."""
    power = 0.0
    for b in range(first, stop):
        power += kick_body_planar(bodies, b, gravity, dt, damping, damp_gravity)
    return power


@njit(cache=True, error_model="numpy", _nrt=False)
def kick(bodies, gravity, dt, damping, damp_gravity, planar=False):
    """:func:`kick_planar` if ``planar``, else :func:`kick_general`, of every body."""
    n = bodies.mass.shape[0]
    if planar:
        return kick_planar(bodies, gravity, dt, damping, damp_gravity, 0, n)
    return kick_general(bodies, gravity, dt, damping, damp_gravity, 0, n)


@inline_kernel()
def drift_body(bodies, b, dt):
    """Position and orientation of body b, n -> n+1, from its half-step velocities."""
    if bodies.held[b]:
        return
    for k in range(3):
        bodies.pos[b, k] += dt * bodies.vel[b, k]
    mode = bodies.rot_mode[b]
    q = bodies.quat
    if mode == ROT_NONE:
        return
    if mode == ROT_FREE:
        R = bodies.rot
        L = bodies.angmom
        inertia = bodies.inertia
        l0 = R[b, 0, 0] * L[b, 0] + R[b, 1, 0] * L[b, 1] + R[b, 2, 0] * L[b, 2]
        l1 = R[b, 0, 1] * L[b, 0] + R[b, 1, 1] * L[b, 1] + R[b, 2, 1] * L[b, 2]
        l2 = R[b, 0, 2] * L[b, 0] + R[b, 1, 2] * L[b, 1] + R[b, 2, 2] * L[b, 2]
        # NO_SQUISH splitting: half turns about axes 0 and 1, a full turn about 2
        l0, l1, l2 = _turn_body_axis(q, b, l0, l1, l2, 0, 0.5 * dt * l0 / inertia[b, 0])
        l0, l1, l2 = _turn_body_axis(q, b, l0, l1, l2, 1, 0.5 * dt * l1 / inertia[b, 1])
        l0, l1, l2 = _turn_body_axis(q, b, l0, l1, l2, 2, dt * l2 / inertia[b, 2])
        l0, l1, l2 = _turn_body_axis(q, b, l0, l1, l2, 1, 0.5 * dt * l1 / inertia[b, 1])
        l0, l1, l2 = _turn_body_axis(q, b, l0, l1, l2, 0, 0.5 * dt * l0 / inertia[b, 0])
    else:
        _turn_world(q, b, bodies.omega[b, 0], bodies.omega[b, 1], bodies.omega[b, 2], dt)
    _normalise(q, b)
    _store_matrix(bodies.rot, b, q[b, 0], q[b, 1], q[b, 2], q[b, 3])
    if mode == ROT_FREE:
        _omega_from_angmom(bodies.rot, bodies.inertia, bodies.angmom, bodies.omega, b)


@inline_kernel()
def _turn_about_y(q, b, wy, dt):
    """q[b] <- exp(omega dt) * q[b] for omega = (0, wy, 0): :func:`_turn_world` without
    the products with the zero components (the same results to the bit)."""
    if wy == 0.0:
        return
    a0, s = _half_turn(wy * wy, dt)
    a2 = wy * s
    q0, q1, q2, q3 = q[b, 0], q[b, 1], q[b, 2], q[b, 3]
    q[b, 0] = a0 * q0 - a2 * q2
    q[b, 1] = a0 * q1 + a2 * q3
    q[b, 2] = a0 * q2 + a2 * q0
    q[b, 3] = a0 * q3 - a2 * q1


@inline_kernel()
def drift_body_planar(bodies, b, dt):
    """:func:`drift_body` of a body of a planar scene, without the components that stay
    zero (the same results to the bit, as :func:`kick_body_planar`)."""
    if bodies.held[b]:
        return
    bodies.pos[b, 0] += dt * bodies.vel[b, 0]
    bodies.pos[b, 2] += dt * bodies.vel[b, 2]
    if bodies.rot_mode[b] == ROT_NONE:
        return
    q = bodies.quat
    _turn_about_y(q, b, bodies.omega[b, 1], dt)
    _normalise(q, b)
    _store_matrix(bodies.rot, b, q[b, 0], q[b, 1], q[b, 2], q[b, 3])


@inline_kernel()
def advance_body_planar(bodies, b, gravity, dt, damping, damp_gravity):
    """:func:`kick_body_planar` then :func:`drift_body_planar` in one go, for the steps in
    which nothing reads the state between the two (engine._body_pass): the same
    positions, velocities and orientations to the bit, without what only readers need --
    the full-step velocities (``vel_full``, ``omega_full``, ``angmom_full``), the half-step
    ``angmom``, the damping power, and row y of the rotation matrix (for a turn about e_y
    it stays (0, 1, 0) to round-off).  These are stale after a fused step, and nothing can
    see them: engine.run_loop fuses a step only when no recorder, check or ledger reads
    the state in it, the last step before every return to Python is not fused (``last``
    makes it a check step), and the returns that grow buffers happen before a step changes
    anything; the next kick and drift with a reader write them all afresh."""
    if bodies.held[b]:
        return
    h = _kick_length(bodies, b, dt)
    inv_m = 1.0 / bodies.mass[b]
    for k in (0, 2):
        if not bodies.blocked[b, k]:
            v = bodies.vel[b, k]
            a = _accelerate(bodies.force[b, k] * inv_m, gravity[k], v, dt, damping, damp_gravity)[0]
            v_new = v + h * a
            bodies.vel[b, k] = v_new
            bodies.pos[b, k] += dt * v_new
        else:
            bodies.pos[b, k] += dt * bodies.vel[b, k]
    if bodies.rot_mode[b] == ROT_NONE:
        return
    w = bodies.omega[b, 1]
    if not bodies.blocked[b, 4]:
        alpha = _spin_acceleration(bodies, b)[0]
        w += h * (damped(alpha, w, dt, damping) if damping != 0.0 else alpha)
        bodies.omega[b, 1] = w
    q = bodies.quat
    _turn_about_y(q, b, w, dt)
    _normalise(q, b)
    _store_rows_xz(bodies.rot, b, q[b, 0], q[b, 1], q[b, 2], q[b, 3])


@inner_kernel(_nrt=False)
def drift_general(bodies, dt, first, stop):
    """Positions and orientations n -> n+1 from the half-step velocities, of the bodies
    ``first .. stop - 1``, which hold every body not held (:func:`kick_general`)."""
    for b in range(first, stop):
        drift_body(bodies, b, dt)


@inner_kernel(_nrt=False)
def drift_planar(bodies, dt, first, stop):
    """:func:`drift_general` for a planar scene (:func:`drift_body_planar`)."""
    for b in range(first, stop):
        drift_body_planar(bodies, b, dt)


@njit(cache=True, error_model="numpy", _nrt=False)
def drift(bodies, dt, planar=False):
    """:func:`drift_planar` if ``planar``, else :func:`drift_general`, of every body."""
    n = bodies.mass.shape[0]
    if planar:
        drift_planar(bodies, dt, 0, n)
    else:
        drift_general(bodies, dt, 0, n)


@inline_kernel()
def _place_spheres(bodies, spheres, count, listed_only, planar):
    """World centres ``x_b + R_b u_s`` of spheres ``0 .. count-1`` (``listed_only``: of
    ``spheres.listed[:count]``).  The owner's position and rotation matrix are loaded into
    registers when the owner changes: once per body, as Scene.build numbers the spheres
    body by body.  ``planar`` (a planar scene, planar.py): ``y = y_b`` exactly, without
    the ~1e-17 m that the round-off of the y row of R adds."""
    pos, rot, local, out = bodies.pos, bodies.rot, spheres.local, spheres.pos
    owner = -1
    x0 = x1 = x2 = r00 = r01 = r02 = r10 = r11 = r12 = r20 = r21 = r22 = 0.0
    for k in range(count):
        # (unsigned indices: numba adds no negative-index wraparound to every access)
        s = np.uint64(spheres.listed[k] if listed_only else k)
        b = spheres.body[s]
        if b != owner:
            owner = b
            x0, x1, x2 = pos[b, 0], pos[b, 1], pos[b, 2]
            r00, r01, r02 = rot[b, 0, 0], rot[b, 0, 1], rot[b, 0, 2]
            r10, r11, r12 = rot[b, 1, 0], rot[b, 1, 1], rot[b, 1, 2]
            r20, r21, r22 = rot[b, 2, 0], rot[b, 2, 1], rot[b, 2, 2]
        u0, u1, u2 = local[s, 0], local[s, 1], local[s, 2]
        out[s, 0] = x0 + r00 * u0 + r01 * u1 + r02 * u2
        out[s, 1] = x1 if planar else x1 + r10 * u0 + r11 * u1 + r12 * u2
        out[s, 2] = x2 + r20 * u0 + r21 * u1 + r22 * u2


@njit(cache=True, error_model="numpy", _nrt=False)
def update_sphere_positions(bodies, spheres, planar):
    """World centres of all spheres from their owners' COM and orientation (``planar``:
    see :func:`_place_spheres`)."""
    _place_spheres(bodies, spheres, spheres.body.shape[0], False, planar)


@inner_kernel(_nrt=False)
def update_listed_sphere_positions(bodies, spheres, planar):
    """World centres of the spheres in the Verlet list (``spheres.listed``): between two
    list builds no other sphere can touch anything, and only these are read."""
    _place_spheres(bodies, spheres, spheres.n_listed[0], True, planar)

"""Contact laws and contact geometry of the hinged-domino model, one pair at a time.

Every function here is a pure, compiled function of one contact: the driver in
:mod:`dominowave.rods.kernel` maps them over the neighbour pairs of the chain.

Frames and signs (SI units throughout)
--------------------------------------
Domino ``i`` turns about its pivot ``A_i = (i p, 0)`` (``p = d + s`` the pitch, the pivot at
the *front bottom edge*). Its angle ``theta`` is positive when it topples forward (+x). A
point with body coordinates ``(u, w)`` (``u`` across the domino, ``-s <= u <= 0``; ``w``
along it, ``0 <= w <= l``) sits at ``X = A + u e_u + w e_w`` with

    e_u = ( cos theta, -sin theta),   e_w = (sin theta, cos theta),

so ``dX/dtheta = -u e_w + w e_u``. The back face is ``u = -s`` (outward normal ``-e_u``), the
front face ``u = 0`` (outward normal ``+e_u``).

A *corner* (a top edge, a point in 2D) of domino ``a`` touches a *face* of domino ``b``.
The overlap ``delta`` is the depth of the corner behind the face; the force on ``b`` is
``F n`` at the face point (``n`` the inward face normal), ``-F n`` on ``a`` at the corner.
Because ``F = dU/d delta`` with ``delta(theta_a, theta_b)`` a function of the angles only,
the generalised forces ``Q_a = -F d delta/d theta_a``, ``Q_b = -F d delta/d theta_b`` are
exact gradients and an undamped chain conserves energy.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = [
    "corner_face_overlap",
    "coulomb_friction",
    "damping_coefficient",
    "hertz_energy",
    "hertz_force",
    "linear_energy",
    "linear_force",
]


# --------------------------------------------------------------------------------------
# Normal force laws: F(delta, delta_dot) >= 0 [N]; delta [m], delta_dot [m/s]
# --------------------------------------------------------------------------------------
@njit(cache=True)
def linear_force(delta, delta_dot, k, c):
    """Linear spring-dashpot (Cundall & Strack 1979; the paper's "linear" law, eqs 21-24).

    ``F = k delta + c delta_dot``, clipped at 0 so that the dashpot never pulls the
    bodies together. ``k`` [N/m] is the stiffness of *the contact* (the paper's ``k_r``).
    """
    f = k * delta + c * delta_dot
    return f if f > 0.0 else 0.0


@njit(cache=True)
def linear_energy(delta, k):
    """Elastic energy ``k delta^2 / 2`` [J] of the linear spring."""
    return 0.5 * k * delta * delta


@njit(cache=True)
def hertz_force(delta, delta_dot, k, c):
    """Hertzian spring with a linear dashpot: ``F = k delta^(3/2) + c delta_dot`` (>= 0).

    ``k`` [N/m^1.5] is the Hertz constant ``(4/3) E* sqrt(R*)`` of the contact (Johnson,
    *Contact Mechanics*, eq. 4.22).
    """
    f = k * delta * math.sqrt(delta) + c * delta_dot
    return f if f > 0.0 else 0.0


@njit(cache=True)
def hertz_energy(delta, k):
    """Elastic energy ``(2/5) k delta^(5/2)`` [J] of the Hertzian spring."""
    return 0.4 * k * delta * delta * math.sqrt(delta)


@njit(cache=True)
def damping_coefficient(zeta, tangent_stiffness, reduced_mass):
    """Dashpot ``c = 2 zeta sqrt(k_t m_r)`` [N s/m] for damping ratio ``zeta``.

    ``m_r`` is the reduced mass of the contact coordinate computed by the model from its
    own inertia and lever arms (``1 / sum_i (d delta/d theta_i)^2 / I_i``), ``k_t`` the
    tangent stiffness. For the linear law this gives the restitution coefficient
    ``e = exp(-zeta pi / sqrt(1 - zeta^2))`` of a free two-body collision.
    """
    return 2.0 * zeta * math.sqrt(tangent_stiffness * reduced_mass)


@njit(cache=True)
def coulomb_friction(normal_force, slip_velocity, mu, v_reg):
    """Regularised Coulomb friction ``F_t = -mu F_n tanh(v_t / v_reg)`` [N].

    ``slip_velocity`` [m/s] is the velocity of the corner relative to the face along the
    face; the force acts on the corner (the opposite one on the face). ``v_reg`` [m/s] is
    the regularisation speed below which friction behaves as a viscous force.
    """
    return -mu * normal_force * math.tanh(slip_velocity / v_reg)


# --------------------------------------------------------------------------------------
# Geometry of a corner of domino a against a face of domino b
# --------------------------------------------------------------------------------------
@njit(cache=True)
def corner_face_overlap(xa, ca, sa, u0, w0, xb, cb, sb, u_face, sigma):
    """Overlap of the corner ``(u0, w0)`` of domino a with the face ``u = u_face`` of b.

    Parameters: pivot abscissae ``xa, xb`` [m], ``cos``/``sin`` of both angles, the corner's
    body coordinates [m], the face's ``u`` [m] and ``sigma`` (-1 back face, +1 front face).

    Returns ``(delta, w, u, ga, gb, px, py, dpx, dpy)``: the overlap [m] (> 0 = inside),
    the corner's body coordinates ``(u, w)`` in b's frame, the lever arms
    ``ga = d delta/d theta_a`` and ``gb = d delta/d theta_b`` [m], the corner position and
    ``dP/d theta_a`` (world, [m]).
    """
    # corner position and its velocity per unit angular velocity of a
    px = xa + u0 * ca + w0 * sa
    py = -u0 * sa + w0 * ca
    dpx = -u0 * sa + w0 * ca
    dpy = -u0 * ca - w0 * sa
    # body coordinates of the corner in b's frame
    rx = px - xb
    ry = py
    u = rx * cb - ry * sb
    w = rx * sb + ry * cb
    delta = -sigma * (u - u_face)
    # d delta / d theta_a = -sigma e_u(b) . dP/dtheta_a ; d u/d theta_b = -w
    ga = -sigma * (dpx * cb - dpy * sb)
    gb = sigma * w
    return delta, w, u, ga, gb, px, py, dpx, dpy

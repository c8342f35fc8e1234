"""A rounded cuboid rolling over its rounded bottom front edge, and its first touch of
the next one: the finite-r version of ``edge_tipping`` (the sharp box is r = 0).

The domino has outer height ``l`` and thickness ``s`` [m]; its edges are rounded with
radius ``r`` [m] (a core rectangle of (s - 2r) x (l - 2r) swept by a disc of radius r, in
the plane of the fall). It stands on the floor and tips forwards by the tilt ``theta``
[rad], its front bottom edge -- a quarter cylinder about the core's front bottom corner K
-- rolling on the floor without slip (high floor friction). Then K stays at height r and
moves forwards by r theta, and the floor contact C below K is the instantaneous centre.
The centre of mass G sits at (-p, q) = (-(s/2 - r), l/2 - r) from K when upright; tilted,

    G - K = (-p cos theta + q sin theta, p sin theta + q cos theta),
    height of G = r + rho cos(phi),  rho = sqrt(p^2 + q^2),  phi = theta - alpha,
    alpha = atan(p / q)  (the balance tilt),
    |G - C|^2 = rho^2 + r^2 + 2 r rho cos(phi).

With the moment of inertia about G, m k_G^2 (the body's own: ``gyration2`` = k_G^2
[m^2]), the kinetic energy is (1/2) m j(theta) theta'^2 about C, j = k_G^2 + |G - C|^2,
and the energy integral and Lagrange's equation read

    (1/2) j(theta) theta'^2 + g rho cos(phi) = (1/2) j(theta0) omega0^2 + g rho cos(phi0),  (E)
    theta'' = rho sin(phi) (g + r theta'^2) / j(theta).                                  (L)

r = 0 is the sharp box: j = k_G^2 + rho^2 = I_edge / m.

First touch. Domino 1 (identical, upright) has its outer back face a clear gap ``d``
ahead of domino 0's outer front face, so its core's back face is at x = d + r (x from
domino 0's upright front face). The two bodies touch when their cores are 2 r apart. Of
domino 0's core the point nearest to domino 1's core is its top front corner T (the rest
of the core lies behind it, farther from domino 1; T's height r + (l - 2r) cos theta is
within domino 1's core face [r, l - r]), at x_T = -r + r theta + (l - 2r) sin theta, so
they touch when d + r - x_T = 2 r:

    (l - 2 r) sin(theta_c) + r theta_c = d.                                          (C)

No import of dominowave. Units: SI.
"""

from __future__ import annotations

import math

from scipy.optimize import brentq

from reference.edge_tipping import tilt_arrival, tilt_quadrature

G = 9.81  # standard gravity [m/s^2]


def rounded_geometry(l, s, r):
    """(p, q, rho, alpha) [m, m, m, rad]: the centre's offset from the edge's axis K when
    upright, its distance and the balance tilt (module docstring). Needs 0 <= r <= s/2."""
    if not 0.0 <= r <= 0.5 * s:
        raise ValueError(f"r = {r} is outside the valid range [0, s/2 = {0.5 * s}]")
    p, q = 0.5 * s - r, 0.5 * l - r
    return p, q, math.hypot(p, q), math.atan2(p, q)


def _gyration2(l, s, gyration2):
    """k_G^2 [m^2]: the given one, or the uniform sharp cuboid's (l^2 + s^2) / 12."""
    return (l * l + s * s) / 12.0 if gyration2 is None else gyration2


def rounded_fall_time(l, s, r, theta0, omega0, theta1, g=G, gyration2=None):
    """Time [s] for the rounded domino to roll over its edge from tilt ``theta0`` with
    angular velocity ``omega0`` >= 0 [rad/s] to ``theta1`` [rad]: the energy integral (E)
    by quadrature after theta = theta0 + x^2 (which removes the 1/sqrt singularity of a
    start from rest), cos(phi0) - cos(phi) by a product formula. ``gyration2`` = I_G / m
    [m^2] (default: the sharp uniform cuboid's). Relative accuracy ~1e-12 (quad, epsrel
    1e-13). Raises ValueError when the domino cannot get there."""
    _, _, rho, alpha = rounded_geometry(l, s, r)
    k2 = _gyration2(l, s, gyration2)
    phi0 = theta0 - alpha

    def j(phi):
        return k2 + rho * rho + r * r + 2.0 * r * rho * math.cos(phi)

    if omega0 == 0.0 and phi0 <= 0.0:
        raise ValueError(f"theta0 = {theta0} must exceed the balance tilt {alpha}")
    if phi0 < 0.0:  # rising: the slowest point is the balance tilt, or theta1 before it
        phi_top = min(theta1 - alpha, 0.0)
        needed = math.sqrt(2.0 * g * rho * (math.cos(phi_top) - math.cos(phi0)) / j(phi0))
        if omega0 <= needed:
            raise ValueError(
                f"omega0 = {omega0} does not get the domino there: it needs > {needed}"
            )
    energy0 = j(phi0) * omega0**2

    def integrand(x):
        half = 0.5 * x * x
        if x == 0.0:
            if omega0 > 0.0:
                return 0.0
            return 2.0 / math.sqrt(2.0 * g * rho * math.sin(phi0) / j(phi0))
        drop = 2.0 * math.sin(phi0 + half) * math.sin(half)  # cos(phi0) - cos(phi)
        return 2.0 * x * math.sqrt(j(phi0 + x * x) / (energy0 + 2.0 * g * rho * drop))

    return tilt_quadrature(integrand, theta0, theta1, alpha)


def rounded_fall_by_lagrange(l, s, r, theta0, omega0, theta1, g=G, gyration2=None):
    """The same roll by Lagrange's equation (L): (time [s], angular velocity [rad/s]) at
    tilt ``theta1``. scipy DOP853, rtol 1e-12, atol 1e-14, the arrival by an event."""
    _, _, rho, alpha = rounded_geometry(l, s, r)
    k2 = _gyration2(l, s, gyration2)

    def acceleration(theta, omega):
        phi = theta - alpha
        j = k2 + rho * rho + r * r + 2.0 * r * rho * math.cos(phi)
        return rho * math.sin(phi) * (g + r * omega**2) / j

    return tilt_arrival(acceleration, theta0, omega0, theta1)


def rounded_contact_tilt(l, s, r, d):
    """Tilt [rad] of first touch, the root of (l - 2r) sin(theta) + r theta = d (eq C) in
    (0, pi/2), by brentq to 1e-15. Needs 0 < d < l - 2r + r pi/2 (else it lands first)."""
    rounded_geometry(l, s, r)
    reach = l - 2.0 * r + 0.5 * math.pi * r
    if not 0.0 < d < reach:
        raise ValueError(f"d = {d} is outside the valid range (0, {reach})")
    return brentq(lambda t: (l - 2.0 * r) * math.sin(t) + r * t - d, 0.0, 0.5 * math.pi, xtol=1e-15)


def rounded_first_contact_time(l, s, r, d, omega, g=G, gyration2=None):
    """(time [s], tilt [rad]) at which rounded domino 0, pushed upright with ``omega``
    [rad/s] (rolling on its front bottom edge, the floor contact at rest), first touches
    rounded domino 1 at clear gap ``d`` [m]: tilt by (C), time by (E) by quadrature."""
    tilt = rounded_contact_tilt(l, s, r, d)
    return rounded_fall_time(l, s, r, 0.0, omega, tilt, g, gyration2), tilt

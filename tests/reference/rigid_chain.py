"""Rigid dominoes hinged at their base: falls and collisions of Efimov & Jenkins (EJ).

The paper's rigid model (eqs 2-14): a domino of height ``l`` is a point mass ``m`` at the
tip of a massless rod hinged at its base, moment of inertia ``I = m l^2`` about the
hinge, tilt ``theta`` from the vertical [rad]. Falling, it obeys Newton's law

    theta'' = (g / l) sin(theta),                                  (N)

whose energy integral is eq 11, theta'^2 = Omega_n^2 + (2 g / l)(1 - cos theta). At
theta = beta = asin(d / l) its tip strikes the next domino; the collision (eq 2)
conserves the energy and the angular momentum about the struck domino's hinge.

Every function here computes from these laws alone (quadrature, root finding, scipy's
solve_ivp); none imports ``dominowave.theory``, whose closed forms they check.
Units: SI throughout (m, s, rad, rad/s, kg).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

G = 9.81  # standard gravity [m/s^2]


def ej_fall_time(omega, beta, l, g=G):
    """Time [s] for an EJ domino to fall from upright (angular velocity ``omega`` > 0
    [rad/s]) to ``beta`` [rad]: eq 11 by quadrature,

        T = int_0^beta dtheta / sqrt(Omega^2 + (2 g / l)(1 - cos theta)).

    With w = Omega sqrt(l / g) and 1 - cos(theta) = 2 sin^2(theta / 2), the substitution
    sinh(u) = 2 sin(theta / 2) / w turns the integrand into the smooth
    sqrt(l / g) / cos(theta / 2): a slowly started domino (w -> 0, beta -> pi/2) has a
    near-logarithmic peak at theta = 0 that plain quadrature cannot resolve to 1e-10.
    Relative accuracy ~1e-13 (quad, epsrel 1e-13).
    """
    w = omega * math.sqrt(l / g)

    def integrand(u):
        return 1.0 / math.sqrt(1.0 - (0.5 * w * math.sinh(u)) ** 2)  # 1 / cos(theta/2)

    u_max = math.asinh(2.0 * math.sin(beta / 2.0) / w)
    value, _ = quad(integrand, 0.0, u_max, epsabs=0.0, epsrel=1e-13, limit=400)
    return math.sqrt(l / g) * value


def fall_by_newton(theta0, omega0, beta, l, g=G):
    """Integrate Newton's law (N) from tilt ``theta0`` [rad] and angular velocity
    ``omega0`` [rad/s] until the tilt reaches ``beta``: (time taken [s], angular velocity
    there [rad/s]). scipy DOP853, rtol 1e-13, atol 1e-15, the arrival located by an event."""

    def hit(_t, y):
        return y[0] - beta

    hit.terminal, hit.direction = True, 1
    sol = solve_ivp(
        lambda _t, y: [y[1], g / l * math.sin(y[0])],
        (0, 1e3),
        [theta0, omega0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-15,
        events=hit,
    )
    return sol.t_events[0][0], sol.y_events[0][0][1]


def ej_collision(omega_f, beta):
    """Eq 2 solved numerically: (Omega_{n+1}, Omega_b) [rad/s] after domino n strikes the
    upright domino n+1 at angular velocity ``omega_f`` > 0 and tilt ``beta``.

    The tip of n moves along xi with speed l Omega_f and meets n+1 at height l cos(beta),
    whose velocity along xi is l cos^2(beta) Omega_{n+1}. Conservation of angular
    momentum about the hinge of n+1 gives Omega_{n+1} = cos^2(beta) (Omega_f - Omega_b);
    of energy, Omega_f^2 = Omega_b^2 + Omega_{n+1}^2. Eliminating Omega_{n+1} leaves one
    equation in Omega_b with the trivial root Omega_b = Omega_f; the physical root lies in
    [-Omega_f, 0] (the striker bounces back) and is found by brentq to rtol 1e-15.
    """
    c = math.cos(beta) ** 2

    def energy_residual(omega_b):
        return omega_f**2 - omega_b**2 - (c * (omega_f - omega_b)) ** 2

    omega_b = brentq(energy_residual, -omega_f, 0.0, xtol=1e-300, rtol=1e-15)
    return c * (omega_f - omega_b), omega_b


def ej_chain_by_newton(n_dominoes, omega_1, beta, l, g=G):
    """Start times [s] of dominoes 0..N-1 (shape (N,)) of a rigid EJ chain: each falls by
    Newton's law (``fall_by_newton``) from upright, then ``ej_collision`` gives the next one
    its angular velocity. Domino 0 starts upright at t = 0 with ``omega_1`` [rad/s]."""
    times, t, omega = [0.0], 0.0, omega_1
    for _ in range(n_dominoes - 1):
        duration, omega_f = fall_by_newton(0.0, omega, beta, l, g)
        t += duration
        omega, _ = ej_collision(omega_f, beta)
        times.append(t)
    return np.array(times)


def ej_transfer_factor(beta):
    """f_+ = Omega_{n+1} / Omega_f = 2 / (cos^2 beta + 1 / cos^2 beta) (eq 4): the root of
    ``ej_collision`` in closed form (the two conservation laws are a quadratic in Omega_b)."""
    c2 = math.cos(beta) ** 2
    return 2.0 / (c2 + 1.0 / c2)


def ej_transient_arrivals(n_dominoes, d_over_l, l, omega1, g=G):
    """Rigid EJ transient: arrival times of the wave at dominoes 0..N-1.

    Domino 0 starts upright with angular velocity ``omega1`` at t = 0. Each collision
    maps Omega_n^2 -> f_+^2 Omega_n^2 + b (eq 6), b = (2 g / l) f_+^2 (1 - cos beta) (eq 7),
    beta = asin(d/l); each fall lasts ``ej_fall_time`` (eq 11 by quadrature). The limit
    Omega^2 = b / (1 - f_+^2) is the fixed point of eq 6 (eq 9) and v = d / T(Omega) (eq 14).

    Returns (t, x, v_limit): arrival times [s] (N,), pivot positions [m] (N,), limit
    speed [m/s].
    """
    beta = math.asin(d_over_l)
    f_plus = ej_transfer_factor(beta)
    b = 2.0 * g / l * f_plus**2 * (1.0 - math.cos(beta))
    t = np.zeros(n_dominoes)
    omega2 = omega1**2
    for n in range(1, n_dominoes):
        t[n] = t[n - 1] + ej_fall_time(math.sqrt(omega2), beta, l, g)
        omega2 = f_plus**2 * omega2 + b
    omega_lim = math.sqrt(b / (1.0 - f_plus**2))
    d = d_over_l * l
    v_limit = d / ej_fall_time(omega_lim, beta, l, g)
    return t, d * np.arange(n_dominoes), v_limit


def hinged_fall_time_from_rest(m, inertia, cm_u, cm_w, theta0, theta1, g=G):
    """Time [s] for a rigid body hinged at its base to fall from rest at ``theta0`` to
    ``theta1`` [rad] (any mass distribution: the rod model's dominoes).

    Mass ``m`` [kg], moment of inertia ``inertia`` about the hinge [kg m^2], centre of
    mass at (cm_u, cm_w) [m] in body coordinates (w along the domino, u across it, so its
    height is h(theta) = -cm_u sin(theta) + cm_w cos(theta)). Energy:

        (1/2) I theta'^2 = m g (h(theta0) - h(theta)),
        t = int_theta0^theta1 dtheta / theta'.

    The substitution theta = theta0 + x^2 removes the 1/sqrt singularity at the start;
    the height drop is evaluated by sum-to-product identities, without cancellation.
    Relative accuracy ~1e-12 (quad, epsrel 1e-12).
    """

    def drop(x):
        # h(theta0) - h(theta0 + x^2)
        mid = theta0 + 0.5 * x * x
        half = math.sin(0.5 * x * x)
        dh = 2.0 * half * (cm_u * math.cos(mid) + cm_w * math.sin(mid))
        return 2.0 * m * g * dh / inertia

    def integrand(x):
        if x == 0.0:  # series limit: drop ~ (2 m g (cm_u cos + cm_w sin)(theta0) / I) x^2
            slope = cm_u * math.cos(theta0) + cm_w * math.sin(theta0)
            return 2.0 / math.sqrt(2.0 * m * g * slope / inertia)
        return 2.0 * x / math.sqrt(drop(x))

    value, _ = quad(integrand, 0.0, math.sqrt(theta1 - theta0), epsabs=0, epsrel=1e-12, limit=200)
    return value

"""Compliant collisions of hinged dominoes: a linear spring acting during the contact.

Two dominoes hinged at their bases, both of moment of inertia ``I`` about the hinge, meet
at a contact whose overlap is delta = g_a phi - g_b psi (phi, psi the rotations of the
striker and the struck domino during the contact, g_a, g_b > 0 the lever arms of the
contact force about their hinges). A linear spring F = k delta (force only while
delta > 0) acts on both; gravity and the change of geometry during the short contact are
neglected, as in the paper's section 2.3 (eqs 15-31).

Every function computes from Newton's law alone (closed form or scipy's solve_ivp);
none imports ``dominowave.theory``. Units: SI (m, s, rad, rad/s, kg, N/m).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from .rigid_chain import G, fall_by_newton


def linear_contact(ga, gb, inertia, k, omega):
    """Closed-form collision of two hinged bodies through a linear spring, the struck
    body at rest: (duration [s], striker's angular velocity after, struck body's after).

    Newton about each hinge, I phi'' = -F g_a and I psi'' = F g_b, gives
    delta'' = -(g_a^2 / I + g_b^2 / I) k delta: a half sine of duration
    pi sqrt(m_r / k), m_r = 1 / (g_a^2 / I + g_b^2 / I). The elastic impulse is
    J = 2 m_r delta'(0) = 2 m_r g_a omega, so omega_a' = omega - J g_a / I and
    omega_b' = J g_b / I.

    ``ga``, ``gb`` lever arms [m]; ``inertia`` about the hinge [kg m^2]; ``k`` [N/m];
    ``omega`` the striker's angular velocity at contact [rad/s].
    """
    m_r = 1.0 / (ga * ga / inertia + gb * gb / inertia)
    duration = math.pi * math.sqrt(m_r / k)
    impulse = 2.0 * m_r * ga * omega
    return duration, omega - impulse * ga / inertia, impulse * gb / inertia


def head_on_contact(omega_f, beta, k_r, m, l, striker_fixed=False):
    """Newton's law for the two EJ dominoes of the paper's Fig 3 during a linear-spring
    contact, integrated until the contact opens.

    Frozen geometry (rotations during the contact are small, as the paper assumes):
    domino n (I = m l^2) turns by ``phi``, its tip moving l phi along xi (perpendicular to
    it); domino n+1 turns by ``psi``, its struck point (height l cos b) moving
    l cos(b) psi horizontally, i.e. l cos^2(b) psi along xi. Overlap
    delta = l phi - l cos^2(b) psi; force F = k_r delta along xi, with moment arm l
    about hinge n and l cos^2 b about hinge n+1 (``linear_contact`` with g_a = l,
    g_b = l cos^2 b). ``striker_fixed``: domino n keeps its angular velocity (infinite
    inertia), so the spring acts on domino n+1 alone.

    scipy DOP853, rtol 1e-12, atol 1e-16, the opening located by an event.
    ``omega_f`` [rad/s], ``beta`` [rad], ``k_r`` [N/m], ``m`` [kg], ``l`` [m].
    Returns (duration [s], omega_n after [rad/s], omega_{n+1} after [rad/s],
    psi at the end [rad], peak force [N] on 4001 samples of the contact).
    """
    c = math.cos(beta) ** 2
    inertia = m * l**2

    def rhs(_t, y):
        phi, psi, dphi, dpsi = y
        force = k_r * max(l * phi - l * c * psi, 0.0)
        striker = 0.0 if striker_fixed else -force * l / inertia
        return [dphi, dpsi, striker, force * l * c / inertia]

    def opens(t, y):
        return (l * y[0] - l * c * y[1]) if t > 0 else 1.0

    opens.terminal, opens.direction = True, -1
    t_guess = math.pi * math.sqrt(m / c**2 / k_r)  # the longest: striker of infinite mass
    sol = solve_ivp(
        rhs,
        (0, 10 * t_guess),
        [0.0, 0.0, omega_f, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-16,
        events=opens,
        dense_output=True,
    )
    duration = sol.t_events[0][0]
    _phi, psi, dphi, dpsi = sol.y_events[0][0]
    t = np.linspace(0, duration, 4001)
    phi_t, psi_t = sol.sol(t)[:2]
    peak_force = k_r * np.max(l * phi_t - l * c * psi_t)
    return duration, dphi, dpsi, psi, peak_force


def thick_chain_speed(beta, s_over_l, k_r, omega_1, m, l, g=G, n_dominoes=6):
    """Wave speed [m/s] of a simulated chain of thick compliant dominoes.

    Bases at x_n = n (d + s), d = l sin(beta), s = (s/l) l (domino n occupies
    [x_n - s, x_n] and pivots on its front edge); the tip of n meets the back face of n+1
    when l sin(theta) = x_{n+1} - s - x_n. Each free fall by Newton's law
    (``fall_by_newton``), each contact integrated (``head_on_contact`` with spring
    ``k_r`` [N/m]), the struck domino falling on from the angle and angular velocity the
    contact left it with; domino 0 starts upright with ``omega_1`` [rad/s]. Returns
    distance / time between the contact onsets of the second and the last collision.
    """
    s, d = s_over_l * l, l * math.sin(beta)
    x = np.arange(n_dominoes) * (d + s)
    onsets, t, psi, omega = [], 0.0, 0.0, omega_1
    for n in range(n_dominoes - 1):
        hit_angle = math.asin((x[n + 1] - s - x[n]) / l)  # geometry of the thick chain
        falling, omega_f = fall_by_newton(psi, omega, hit_angle, l, g)
        t += falling
        onsets.append(t)
        duration, _, omega, psi, _ = head_on_contact(omega_f, hit_angle, k_r, m, l)
        t += duration
    return (x[-2] - x[1]) / (onsets[-1] - onsets[1])

"""A rigid cuboid tipping over its bottom front edge, and its first touch of the next one.

A uniform box of height ``l`` and thickness ``s`` [m] (any width) turns about its bottom
front edge, which stays fixed on the floor (no slip, no lift-off). Tilt ``theta`` [rad]
from upright, positive forwards. Seen from the edge, the centre of mass G sits at

    rho = sqrt(l^2 + s^2) / 2  along the half diagonal, alpha = atan(s / l) behind the
    vertical at theta = 0,  so G = rho (sin(phi), cos(phi)),  phi = theta - alpha

(x forwards, z up). Its height rho cos(phi) is highest at theta = alpha: the box balances
on its edge there. With I_edge = m (l^2 + s^2) / 3 = (4/3) m rho^2 about the edge,

    theta'' = (m g rho / I_edge) sin(theta - alpha) = (3 g / (4 rho)) sin(theta - alpha), (T)
    theta'^2 = omega0^2 + (3 g / (2 rho)) (cos(phi0) - cos(phi)),                     (E)

the energy integral (E) from (theta0, omega0). A thin box (s -> 0) is the uniform rod,
theta'' = (3 g / 2 l) sin theta. The box lands flat at theta = pi/2.

First touch (domino 1 identical, upright, its back face a clear gap ``d`` ahead of the
front face of domino 0, so at x = d). Rotated by theta, a point (x, z) of domino 0 moves
to (x cos theta + z sin theta, -x sin theta + z cos theta); over its rectangle
-s <= x <= 0, 0 <= z <= l the largest forward coordinate is the top front corner's,
l sin theta (the top back corner's, l sin theta - s cos theta, is smaller for theta <
pi/2). That corner is at height l cos theta <= l, on domino 1's back face, so the first
contact is the top front edge of domino 0 on the back face of domino 1 at

    sin(theta_c) = d / l,                                                          (C)

whatever the thickness (it needs d < l). The thickness enters the time only, through
rho, alpha and I_edge in (E). No import of dominowave. Units: SI.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

G = 9.81  # standard gravity [m/s^2]


def edge_geometry(l, s):
    """(rho [m], alpha [rad], rate^2 = 3 g / (4 rho) per unit g [1/m]) of a box of height
    ``l`` and thickness ``s`` tipping over its edge: half diagonal, balance tilt atan(s/l),
    and m rho / I_edge."""
    rho = 0.5 * math.hypot(l, s)
    return rho, math.atan2(s, l), 0.75 / rho


def edge_fall_time(l, s, theta0, omega0, theta1, g=G):
    """Time [s] for the box to tip from tilt ``theta0`` with angular velocity ``omega0``
    >= 0 [rad/s] to ``theta1`` > theta0 [rad]: the energy integral (E) by quadrature,

        t = int_theta0^theta1 dtheta / sqrt(omega0^2 + (3 g / 2 rho)(cos phi0 - cos phi)).

    The substitution theta = theta0 + x^2 removes the 1/sqrt singularity of a start from
    rest; cos phi0 - cos phi = 2 sin((phi + phi0)/2) sin((phi - phi0)/2) is evaluated
    without cancellation. Raises ValueError when the box cannot get there (from rest
    behind its balance tilt alpha, or a push too weak to carry it over alpha).
    Relative accuracy ~1e-12 (quad, epsrel 1e-13)."""
    _, alpha, rate2 = edge_geometry(l, s)
    k = 2.0 * rate2 * g  # 3 g / (2 rho)
    phi0 = theta0 - alpha
    if omega0 == 0.0 and phi0 <= 0.0:
        raise ValueError(f"theta0 = {theta0} must exceed the balance tilt atan(s/l) = {alpha}")
    if phi0 < 0.0:  # rising: the slowest point is the balance tilt, or theta1 before it
        phi_top = min(theta1 - alpha, 0.0)
        needed = math.sqrt(k * (math.cos(phi_top) - math.cos(phi0)))
        if omega0 <= needed:
            raise ValueError(f"omega0 = {omega0} does not get the box there: it needs > {needed}")

    def speed2(x):
        half = 0.5 * x * x
        return omega0**2 + 2.0 * k * math.sin(phi0 + half) * math.sin(half)

    def integrand(x):
        if x == 0.0:
            if omega0 > 0.0:
                return 0.0
            return 2.0 / math.sqrt(k * math.sin(phi0))  # speed2 ~ k sin(phi0) x^2
        return 2.0 * x / math.sqrt(speed2(x))

    return tilt_quadrature(integrand, theta0, theta1, alpha)


def tilt_quadrature(integrand, theta0, theta1, alpha):
    """int_0^sqrt(theta1 - theta0) integrand(x) dx [s], x^2 = theta - theta0: a fall time
    after the substitution, the balance tilt ``alpha`` (where the speed is least) a
    breakpoint. quad, epsrel 1e-13."""
    points = [math.sqrt(alpha - theta0)] if theta0 < alpha < theta1 else None
    value, _ = quad(
        integrand,
        0.0,
        math.sqrt(theta1 - theta0),
        epsabs=0.0,
        epsrel=1e-13,
        limit=400,
        points=points,
    )
    return value


def tilt_arrival(acceleration, theta0, omega0, theta1):
    """Integrate theta'' = acceleration(theta, theta') from (``theta0``, ``omega0``) until
    the tilt reaches ``theta1``: (time [s], angular velocity there [rad/s]). scipy DOP853,
    rtol 1e-12, atol 1e-14, the arrival located by an event; ValueError if the body falls
    back instead."""

    def arrive(_t, y):
        return y[0] - theta1

    def fall_back(_t, y):
        return y[0] - theta0 + 1.0  # far behind the start: it did not get over

    arrive.terminal, arrive.direction = True, 1
    fall_back.terminal = True
    sol = solve_ivp(
        lambda _t, y: [y[1], acceleration(y[0], y[1])],
        (0.0, 1e3),
        [theta0, omega0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        events=(arrive, fall_back),
    )
    if not len(sol.t_events[0]):
        raise ValueError(f"the body does not reach theta1 = {theta1} from theta0 = {theta0}")
    return sol.t_events[0][0], sol.y_events[0][0][1]


def edge_fall_by_newton(l, s, theta0, omega0, theta1, g=G):
    """The same fall by Newton's law (T): (time [s], angular velocity there [rad/s]) when
    the tilt reaches ``theta1`` (pi/2: landing flat; or an obstacle's tilt). scipy DOP853,
    rtol 1e-12, atol 1e-14, the arrival located by an event."""
    _, alpha, rate2 = edge_geometry(l, s)
    return tilt_arrival(lambda th, _w: rate2 * g * math.sin(th - alpha), theta0, omega0, theta1)


def edge_reaction(l, s, theta, omega, g=G):
    """Force of the floor on the hinge edge per unit mass [m/s^2], (horizontal, vertical)
    = (a_x, a_z + g) of the centre of mass at tilt ``theta`` [rad] and angular velocity
    ``omega`` [rad/s] (theta'' from (T)). The no-slip assumption holds while |horizontal|
    <= mu vertical and the edge stays down while vertical > 0."""
    rho, alpha, rate2 = edge_geometry(l, s)
    phi = theta - alpha
    acc = rate2 * g * math.sin(phi)
    a_x = rho * (acc * math.cos(phi) - omega**2 * math.sin(phi))
    a_z = -rho * (acc * math.sin(phi) + omega**2 * math.cos(phi))
    return a_x, a_z + g


def edge_slip_tilt(l, s, theta0, omega0, mu, theta_end, g=G):
    """First tilt [rad] in [theta0, theta_end] at which the hinge edge needs more friction
    than ``mu`` (|horizontal| > mu vertical, or the vertical force vanishes), or None when
    the no-slip fall holds up to ``theta_end``. The angular velocity from the energy
    integral (E); a scan of 20000 tilts, the crossing refined by brentq (xtol 1e-14).

    From rest near the balance tilt the floor force is, per unit weight,
    vertical (1 - 3 cos phi)^2 / 4 (phi0 -> 0) -- it vanishes at cos phi = 1/3 while the
    horizontal (3/4) sin phi (3 cos phi - 2) does not: every box slips (or hops) there,
    at theta = alpha + acos(1/3) (79.4 deg for 48 x 7.5 mm), before it lands flat."""
    _, alpha, rate2 = edge_geometry(l, s)
    k = 2.0 * rate2 * g

    def excess(theta):
        omega2 = omega0**2 + k * (math.cos(theta0 - alpha) - math.cos(theta - alpha))
        f_x, f_z = edge_reaction(l, s, theta, math.sqrt(max(omega2, 0.0)), g)
        return abs(f_x) - mu * f_z

    tilts = np.linspace(theta0, theta_end, 20001)
    values = np.array([excess(th) for th in tilts])
    if values[0] > 0.0:
        return theta0
    over = np.nonzero(values >= 0.0)[0]
    if not len(over):
        return None
    i = over[0]
    return brentq(excess, tilts[i - 1], tilts[i], xtol=1e-14)


def first_contact_tilt(l, d):
    """Tilt [rad] at which domino 0 (tipping over its front bottom edge) first touches
    domino 1 standing a clear gap ``d`` ahead: asin(d / l) (eq C), its top front edge on
    domino 1's back face. Needs 0 < d < l."""
    if not 0.0 < d < l:
        raise ValueError(f"d = {d} is outside the valid range (0, l = {l})")
    return math.asin(d / l)


def first_contact_time(l, s, d, omega, g=G):
    """(time [s], tilt [rad]) at which domino 0 of a two-domino chain, pushed upright with
    angular velocity ``omega`` [rad/s] about its front bottom edge (the edge at rest),
    first touches domino 1 (height ``l``, thickness ``s``, clear gap ``d`` [m]): the tilt
    by (C), the time by quadrature of the energy equation (E) from theta0 = 0."""
    tilt = first_contact_tilt(l, d)
    return edge_fall_time(l, s, 0.0, omega, tilt, g), tilt

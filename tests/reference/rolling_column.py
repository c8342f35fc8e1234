"""A rigid column of spheres rolling without slip on its base sphere: the DEM domino's fall.

A column of spheres (masses m_j, centre heights z_j, radii r_j) stands on the sphere of
radius R centred at z = R (the base sphere touches the floor). Tilted by ``theta`` about
the y axis, the base sphere rolls without slipping, so its centre moves by R theta and
sphere j sits at

    x_j = R theta + (z_j - R) sin(theta),   z_j(theta) = R + (z_j - R) cos(theta).

With m = sum m_j, a = z_cm - R the height of the centre of mass above the base sphere's
centre and I_cm the moment of inertia about the centre of mass (y axis), the Lagrangian is

    KE = (1/2) J(theta) theta'^2,  J(theta) = I_cm + m (R^2 + a^2 + 2 R a cos theta),
    PE = m g (R + a cos theta),

with the equation of motion

    J(theta) theta'' - m R a sin(theta) theta'^2 = m g a sin(theta).          (L)

Its energy integral gives the fall time by quadrature (``rolling_column_time``); (L)
integrated by solve_ivp (``rolling_column_by_ode``) is the same motion by another method.
No import of dominowave. Units: SI (m, s, rad, rad/s, kg).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

from .rigid_chain import G


def column_properties(masses, z, radii, base_radius):
    """(m [kg], a [m], I_cm [kg m^2]) of the column: total mass, height of the centre of
    mass above the base sphere's centre, moment of inertia about the centre of mass
    (solid spheres, 2/5 m r^2 each, plus parallel axis). ``masses``, ``z``, ``radii`` (n,)."""
    masses, z, radii = (np.asarray(v, dtype=float) for v in (masses, z, radii))
    m = float(np.sum(masses))
    z_cm = float(np.sum(masses * z) / m)
    i_cm = float(np.sum(masses * (0.4 * radii**2 + (z - z_cm) ** 2)))
    return m, z_cm - base_radius, i_cm


def rolling_column_rate(masses, z, radii, base_radius, omega0, g=G, theta0=0.0):
    """theta'(theta) [rad/s] of the rolling column from energy conservation, starting at
    tilt ``theta0`` [rad] with angular velocity ``omega0`` [rad/s]:

        J(theta) theta'^2 = J(theta0) omega0^2 + 2 m g a (cos theta0 - cos theta),

    the difference of cosines as 2 sin((theta + theta0)/2) sin((theta - theta0)/2), free
    of cancellation near theta0. Returns a function of theta."""
    m, a, i_cm = column_properties(masses, z, radii, base_radius)
    r = base_radius

    def j_of(th):
        return i_cm + m * (r * r + a * a + 2.0 * r * a * math.cos(th))

    start = j_of(theta0) * omega0**2

    def rate(th):
        fall = 4.0 * m * g * a * math.sin(0.5 * (th + theta0)) * math.sin(0.5 * (th - theta0))
        return math.sqrt((start + fall) / j_of(th))

    return rate


def rolling_column_time(masses, z, radii, base_radius, omega0, theta_end, g=G, theta0=0.0):
    """Time [s] for the rolling column to tilt from ``theta0`` (angular velocity
    ``omega0``) to ``theta_end`` [rad]: t = int dtheta / theta'(theta) by quadrature
    (quad, epsrel 1e-12). The substitution theta = theta0 + x^2 keeps the integrand
    2 x / theta' finite when the column starts from rest (theta' ~ x near the start)."""
    m, a, i_cm = column_properties(masses, z, radii, base_radius)
    r = base_radius
    rate = rolling_column_rate(masses, z, radii, base_radius, omega0, g, theta0)
    j0 = i_cm + m * (r * r + a * a + 2.0 * r * a * math.cos(theta0))

    def integrand(x):
        if x == 0.0:
            if omega0 > 0.0:
                return 0.0
            # from rest: theta'^2 ~ 2 m g a sin(theta0) x^2 / J(theta0)
            return 2.0 / math.sqrt(2.0 * m * g * a * math.sin(theta0) / j0)
        return 2.0 * x / rate(theta0 + x * x)

    upper = math.sqrt(theta_end - theta0)
    return quad(integrand, 0.0, upper, epsabs=0.0, epsrel=1e-12, limit=200)[0]


def rolling_column_friction_ratio(
    masses, z, radii, base_radius, omega0, theta_end, g=G, theta0=0.0, samples=2000
):
    """Largest |friction / normal force| at the floor the rolling column needs between
    ``theta0`` and ``theta_end`` (evaluated at ``samples`` tilts): rolling without slip
    holds on a floor of friction coefficient mu only if this ratio stays below mu.

    The floor force equals m times the acceleration of the centre of mass plus m g:
    with alpha = theta'' from (L) and omega = theta' from energy,
    a_x = (R + a cos theta) alpha - a sin(theta) omega^2,
    a_z = -a sin(theta) alpha - a cos(theta) omega^2; ratio |a_x| / (g + a_z)."""
    m, a, i_cm = column_properties(masses, z, radii, base_radius)
    r = base_radius
    rate = rolling_column_rate(masses, z, radii, base_radius, omega0, g, theta0)
    th = np.linspace(theta0, theta_end, samples)
    om = np.array([rate(t) for t in th])
    j = i_cm + m * (r * r + a * a + 2.0 * r * a * np.cos(th))
    al = (m * g * a * np.sin(th) + m * r * a * np.sin(th) * om**2) / j
    ax = (r + a * np.cos(th)) * al - a * np.sin(th) * om**2
    az = -a * np.sin(th) * al - a * np.cos(th) * om**2
    return float(np.max(np.abs(ax) / (g + az)))


def rolling_column_by_ode(masses, z, radii, base_radius, omega0, theta_end, g=G, theta0=0.0):
    """The same fall by integrating (L) with scipy's RK45 (rtol 1e-12, atol 1e-14) until
    the tilt reaches ``theta_end``: (time [s], angular velocity there [rad/s])."""
    m, a, i_cm = column_properties(masses, z, radii, base_radius)
    r = base_radius

    def rhs(_t, y):
        th, om = y
        j = i_cm + m * (r * r + a * a + 2.0 * r * a * math.cos(th))
        return [om, (m * g * a * math.sin(th) + m * r * a * math.sin(th) * om**2) / j]

    def hit(_t, y):
        return y[0] - theta_end

    hit.terminal, hit.direction = True, 1
    sol = solve_ivp(rhs, (0, 10), [theta0, omega0], events=hit, rtol=1e-12, atol=1e-14)
    return sol.t_events[0][0], sol.y_events[0][0][1]


def rolling_column_contact_angle(z, radius, pitch):
    """Tilt [rad] at which a sphere of the rolling column (identical spheres of ``radius``
    [m] at heights ``z`` (n,) [m], base sphere of the same radius) first touches the
    upright column of the same spheres standing ``pitch`` [m] ahead (both on the floor):
    the smallest root of min_jk |p_j(theta) - q_k| = 2 R, bracketed by steps of 0.05 rad
    and found by brentq (xtol 1e-15)."""
    zc = np.asarray(z, dtype=float)

    def gap(th):
        x = radius * th + (zc - radius) * math.sin(th)
        zz = radius + (zc - radius) * math.cos(th)
        d2 = (x[:, None] - pitch) ** 2 + (zz[:, None] - zc[None, :]) ** 2
        return math.sqrt(d2.min()) - 2.0 * radius

    hi = 0.05
    while gap(hi) > 0:
        hi += 0.05
    return brentq(gap, hi - 0.05, hi, xtol=1e-15, rtol=1e-15)

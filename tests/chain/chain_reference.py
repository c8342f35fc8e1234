"""Independent reference computations for the chain tests (no dominowave.theory import)."""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad

G = 9.81


def ej_fall_time(omega, beta, l, g=G):
    """Eq 11 by quadrature: time for a thin rod (point mass at the tip) to fall 0 -> beta."""
    c = 2.0 * g / l

    def integrand(th):
        return 1.0 / math.sqrt(omega**2 + c - c * math.cos(th))

    return quad(integrand, 0.0, beta, epsabs=0.0, epsrel=1e-13, limit=200)[0]


def ej_transient_arrivals(n_dominoes, d_over_l, l, omega1, g=G):
    """Rigid EJ transient: arrival times of the wave at dominoes 0..N-1.

    Domino 0 starts upright with angular velocity omega1 at t = 0; Omega_n from
    the recursion eq 6 (equivalently eq 8), T_n by quadrature of eq 11.
    Returns (t, x, v_limit): arrival times [s], pivot positions [m], eq 14 limit.
    """
    beta = math.asin(d_over_l)
    c2 = math.cos(beta) ** 2
    f_plus = 2.0 / (c2 + 1.0 / c2)  # eq 4
    b = 2.0 * g / l * f_plus**2 * (1.0 - math.cos(beta))  # eq 7
    t = np.zeros(n_dominoes)
    omega2 = omega1**2
    for n in range(1, n_dominoes):
        t[n] = t[n - 1] + ej_fall_time(math.sqrt(omega2), beta, l, g)
        omega2 = f_plus**2 * omega2 + b  # eq 6
    omega_lim = math.sqrt(b / (1.0 - f_plus**2))  # eq 9 (the limit of Omega_n^2 is Omega^2)
    d = d_over_l * l
    v_limit = d / ej_fall_time(omega_lim, beta, l, g)  # eq 14
    return t, d * np.arange(n_dominoes), v_limit


def rolling_column_energy(masses, z, radii, base_radius, omega0, g=G):
    """Energy quadrature pieces of a rigid column rolling without slip on its base sphere.

    Column of spheres (masses (n,), centre heights z (n,), radii (n,)) standing on
    the sphere of radius ``base_radius`` centred at z = base_radius. Tilt theta about
    y; the base sphere rolls, so its centre moves by R theta. Lagrangian:
    KE = 1/2 J(theta) theta'^2, J = I_cm + m (R^2 + a^2 + 2 R a cos theta),
    PE = m g a cos theta, a = z_cm - R. Returns theta'(theta) as a function.
    """
    m = float(np.sum(masses))
    z_cm = float(np.sum(masses * z) / m)
    i_cm = float(np.sum(masses * (0.4 * radii**2 + (z - z_cm) ** 2)))
    r = base_radius
    a = z_cm - r

    def j_of(th):
        return i_cm + m * (r * r + a * a + 2.0 * r * a * math.cos(th))

    energy = 0.5 * j_of(0.0) * omega0**2 + m * g * a

    def rate(th):
        return math.sqrt(2.0 * (energy - m * g * a * math.cos(th)) / j_of(th))

    return rate


def rolling_column_time(masses, z, radii, base_radius, omega0, theta_end, g=G):
    """Time [s] for the rolling column (``rolling_column_energy``) to tilt 0 -> theta_end."""
    rate = rolling_column_energy(masses, z, radii, base_radius, omega0, g)
    return quad(lambda th: 1.0 / rate(th), 0.0, theta_end, epsabs=0.0, epsrel=1e-12, limit=200)[0]


def rolling_column_contact_angle(z, radius, pitch):
    """Tilt at which a sphere of the rolling column first touches the upright column
    of identical spheres (same heights z) a distance ``pitch`` ahead (both on the floor).

    Sphere j of the tilted column: (R theta + (z_j - R) sin theta, R + (z_j - R) cos theta).
    """
    from scipy.optimize import brentq

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


def planar_chain_collisions(
    local, radii, masses_total, inertia_cm, kn, centres0, vel0, g=G, t_end=0.2, max_step=5e-5
):
    """Independent reference: planar rigid bodies with linear normal springs, no friction.

    Bodies (dominoes) move in the xz plane: state (x, z, theta) each; sphere k of a body
    sits at com + Rot(theta) local[k]; every overlapping sphere pair of neighbouring bodies
    and every sphere below z = r (floor) pushes with k_n * overlap along the centre line /
    the vertical. Integrated with scipy's DOP853 (rtol 1e-11); returns the first-contact
    time of body n with body n-1 for n = 1..B-1 (NaN if none before t_end).

    local (S, 2) sphere offsets (x, z) from the COM at theta = 0; radii (S,);
    masses_total, inertia_cm: body mass [kg] and inertia about the COM's y axis [kg m^2];
    centres0 (B, 2) initial COM (x, z); vel0 (B, 3) initial (vx, vz, omega_y).
    """
    from scipy.integrate import solve_ivp

    nb = centres0.shape[0]
    local = np.asarray(local, dtype=float)
    radii = np.asarray(radii, dtype=float)

    def spheres(y):
        x, z, th = y[0 : 3 * nb : 3], y[1 : 3 * nb : 3], y[2 : 3 * nb : 3]
        c, s = np.cos(th)[:, None], np.sin(th)[:, None]
        px = x[:, None] + c * local[None, :, 0] + s * local[None, :, 1]
        pz = z[:, None] - s * local[None, :, 0] + c * local[None, :, 1]
        return px, pz

    def rhs(t, y):
        px, pz = spheres(y)
        fx = np.zeros_like(px)
        fz = np.zeros_like(pz)
        pen = radii[None, :] - pz  # floor
        fz += np.where(pen > 0, kn * pen, 0.0)
        for i in range(nb - 1):
            dx = px[i][:, None] - px[i + 1][None, :]
            dz = pz[i][:, None] - pz[i + 1][None, :]
            d = np.sqrt(dx * dx + dz * dz)
            ov = radii[:, None] + radii[None, :] - d
            f = np.where(ov > 0, kn * ov / d, 0.0)
            fx[i] += (f * dx).sum(axis=1)
            fz[i] += (f * dz).sum(axis=1)
            fx[i + 1] -= (f * dx).sum(axis=0)
            fz[i + 1] -= (f * dz).sum(axis=0)
        x, z = y[0 : 3 * nb : 3], y[1 : 3 * nb : 3]
        torque = ((pz - z[:, None]) * fx - (px - x[:, None]) * fz).sum(axis=1)
        dy = np.empty_like(y)
        dy[: 3 * nb] = y[3 * nb :]
        acc = np.empty(3 * nb)
        acc[0::3] = fx.sum(axis=1) / masses_total
        acc[1::3] = fz.sum(axis=1) / masses_total - g
        acc[2::3] = torque / inertia_cm
        dy[3 * nb :] = acc
        return dy

    def gap_event(i):
        def ev(t, y):
            px, pz = spheres(y)
            dx = px[i][:, None] - px[i + 1][None, :]
            dz = pz[i][:, None] - pz[i + 1][None, :]
            return float(np.min(np.sqrt(dx * dx + dz * dz) - radii[:, None] - radii[None, :]))

        ev.terminal = False
        ev.direction = -1
        return ev

    y0 = np.concatenate([np.column_stack([centres0, np.zeros(nb)]).ravel(), vel0.ravel()])
    events = [gap_event(i) for i in range(nb - 1)]
    sol = solve_ivp(
        rhs,
        (0.0, t_end),
        y0,
        method="DOP853",
        rtol=1e-11,
        atol=1e-14,
        max_step=max_step,
        events=events,
    )
    return np.array([e[0] if e.size else np.nan for e in sol.t_events])


def chain_collisions(chain, push, t_end, max_step=5e-5):
    """:func:`planar_chain_collisions` for the initial state of a 2D ``DominoChain`` pushed
    by ``push``: the chain supplies only geometry, masses, k_n and the push velocities
    (COM at rest on the sink of its base, domino 0 with the push's (vx, vz, omega_y));
    the integration is independent of the engine."""
    p, shape = chain.params, chain.shape
    com = shape.centre_of_mass
    centres0 = np.array([[x + com[0], com[2] - chain._sink()] for x in chain.positions])
    v0, w0, _ = chain._push_velocities(push)
    vel0 = np.zeros((len(chain.positions), 3))
    vel0[0] = [v0[0], v0[2], w0[1]]
    return planar_chain_collisions(
        (shape.centres - com)[:, [0, 2]],
        shape.radii,
        shape.mass,
        shape.inertia_about_y(com),
        p.contact_stiffness,
        centres0,
        vel0,
        g=p.g,
        t_end=t_end,
        max_step=max_step,
    )

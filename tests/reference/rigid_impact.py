"""Impact of two rigid bodies at one point: the effective mass, Newton's restitution law,
and the same impact through a spring-dashpot at frozen geometry.

Bodies i and j (mass m [kg], inertia tensor I [kg m^2] (3, 3) in the world frame, centre
x [m], velocity v [m/s], angular velocity w [rad/s], all (3,)) touch at the point p with
the unit normal n pointing from i to j. The lever arms are r_i = p - x_i, r_j = p - x_j;
the relative normal velocity of the touching material points is

    u = n . (v_j + w_j x r_j - v_i - w_i x r_i)          (u < 0: approaching).

An impulse J n on j and -J n on i changes u by J / m_eff with

    1 / m_eff = 1/m_i + 1/m_j + (r_i x n) . I_i^-1 (r_i x n) + (r_j x n) . I_j^-1 (r_j x n).

Newton's law u' = -e u (no friction) gives J = -(1 + e) m_eff u and

    v_j += J n / m_j,  w_j += I_j^-1 (r_j x J n),  v_i -= J n / m_i,  w_i -= I_i^-1 (r_i x J n);

the total momentum and the angular momentum about any point are unchanged (both impulses
act at p) and the kinetic energy drops by (1 - e^2) m_eff u^2 / 2.

A linear spring-dashpot F = k delta + c delta' (delta the overlap, delta' = -u) with the
lever arms, normal and inertia frozen makes u obey m_eff delta'' = -F: a damped oscillator
whose overlap returns to zero with u' = -e u, e = exp(-zeta pi / sqrt(1 - zeta^2)),
zeta = c / (2 sqrt(k m_eff)) (the dashpot may pull; the contact ends when delta = 0).
No import of dominowave. Units: SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.integrate import solve_ivp


@dataclass(frozen=True)
class Body:
    """A rigid body's state: mass [kg], world-frame inertia tensor (3, 3) [kg m^2], centre
    (3,) [m], velocity (3,) [m/s], angular velocity (3,) [rad/s]."""

    m: float
    inertia: np.ndarray
    x: np.ndarray
    v: np.ndarray
    w: np.ndarray

    def kinetic_energy(self):
        """(1/2) m v^2 + (1/2) w . I w [J]."""
        return 0.5 * self.m * self.v @ self.v + 0.5 * self.w @ self.inertia @ self.w

    def angular_momentum(self, about):
        """(x - about) x m v + I w [kg m^2/s] about the point ``about`` (3,)."""
        return np.cross(self.x - about, self.m * self.v) + self.inertia @ self.w

    def point_velocity(self, p):
        """Velocity [m/s] of the material point at ``p`` (3,): v + w x (p - x)."""
        return self.v + np.cross(self.w, p - self.x)


def effective_mass(body_i, body_j, p, n):
    """m_eff [kg] of the pair along the unit normal ``n`` at the contact point ``p``."""
    inverse = 1.0 / body_i.m + 1.0 / body_j.m
    for body in (body_i, body_j):
        arm = np.cross(p - body.x, n)
        inverse += arm @ np.linalg.solve(body.inertia, arm)
    return 1.0 / inverse


def normal_velocity(body_i, body_j, p, n):
    """u = n . (velocity of j's point - velocity of i's point) at ``p`` [m/s]."""
    return n @ (body_j.point_velocity(p) - body_i.point_velocity(p))


def apply_impulse(body_i, body_j, p, n, impulse):
    """The two bodies after the impulse ``impulse`` n on j and -``impulse`` n on i at p."""
    out = []
    for body, sign in ((body_i, -1.0), (body_j, 1.0)):
        kick = sign * impulse * n
        w = body.w + np.linalg.solve(body.inertia, np.cross(p - body.x, kick))
        out.append(replace(body, v=body.v + kick / body.m, w=w))
    return tuple(out)


def impulse_collision(body_i, body_j, p, n, e):
    """Frictionless collision with normal restitution ``e`` in [0, 1] (Newton's law):
    (body_i, body_j after, impulse J [N s], m_eff [kg]). Needs u < 0 (approaching)."""
    u = normal_velocity(body_i, body_j, p, n)
    if u >= 0.0:
        raise ValueError(f"normal velocity u = {u} must be < 0 (approaching)")
    m_eff = effective_mass(body_i, body_j, p, n)
    impulse = -(1.0 + e) * m_eff * u
    after_i, after_j = apply_impulse(body_i, body_j, p, n, impulse)
    return after_i, after_j, impulse, m_eff


def energy_loss(m_eff, u, e):
    """Kinetic energy [J] lost in the collision: (1 - e^2) m_eff u^2 / 2."""
    return 0.5 * (1.0 - e * e) * m_eff * u * u


def dashpot_for_restitution(e, k, m_eff):
    """Dashpot coefficient c [N s/m] for restitution ``e`` in (0, 1] of a linear spring
    ``k`` [N/m] on the effective mass ``m_eff`` [kg] (contact ending at zero overlap):
    zeta = -ln e / sqrt(pi^2 + ln^2 e), c = 2 zeta sqrt(k m_eff)."""
    if not 0.0 < e <= 1.0:
        raise ValueError(f"e = {e} is outside the valid range (0, 1]")
    log_e = math.log(e)
    return 2.0 * (-log_e / math.hypot(math.pi, log_e)) * math.sqrt(k * m_eff)


def compliant_impact(body_i, body_j, p, n, k, c):
    """The same impact through the spring-dashpot F = k delta + c delta' along n, Newton's
    and Euler's laws of both bodies integrated at frozen geometry (lever arms, normal and
    inertia tensors fixed: a contact short against the motion), 12 velocities plus the
    overlap, from first touch (delta = 0) until the overlap returns to zero. scipy DOP853,
    rtol 1e-12, atol 1e-15 (relative to the scales), event at delta = 0.

    Returns (body_i, body_j after, contact duration [s])."""
    r_i, r_j = p - body_i.x, p - body_j.x
    inv_i, inv_j = np.linalg.inv(body_i.inertia), np.linalg.inv(body_j.inertia)

    def rhs(_t, y):
        v_i, w_i, v_j, w_j, delta = y[0:3], y[3:6], y[6:9], y[9:12], y[12]
        u = n @ (v_j + np.cross(w_j, r_j) - v_i - np.cross(w_i, r_i))
        force = (k * delta - c * u) * n  # on j; delta' = -u
        return np.concatenate(
            (
                -force / body_i.m,
                -inv_i @ np.cross(r_i, force),
                force / body_j.m,
                inv_j @ np.cross(r_j, force),
                [-u],
            )
        )

    def separated(_t, y):
        return y[12]

    separated.terminal, separated.direction = True, -1
    u0 = normal_velocity(body_i, body_j, p, n)
    m_eff = effective_mass(body_i, body_j, p, n)
    period = 2.0 * math.pi * math.sqrt(m_eff / k)
    y0 = np.concatenate((body_i.v, body_i.w, body_j.v, body_j.w, [0.0]))
    sol = solve_ivp(
        rhs,
        (0.0, 10.0 * period),
        y0,
        method="DOP853",
        rtol=1e-12,
        atol=1e-15 * max(abs(u0), 1.0) * period,
        events=separated,
        first_step=1e-6 * period,
    )
    y = sol.y_events[0][0]
    after_i = replace(body_i, v=y[0:3], w=y[3:6])
    after_j = replace(body_j, v=y[6:9], w=y[9:12])
    return after_i, after_j, sol.t_events[0][0]

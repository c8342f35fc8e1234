"""A rigid block on an incline with Coulomb friction: sticking, sliding and tipping.

The incline rises at angle ``t`` [rad]; the block's base has length ``s`` [m] along the
slope (the domino's thickness), its centre of mass G lies at height ``h`` [m] above the
base, over the middle of the base. One friction coefficient ``mu`` (static = kinetic).
Along the slope, downhill positive, with the normal force N = m g cos t:

    m x'' = m g sin t - F,   |F| <= mu N;

sticking needs F = m g sin t <= mu m g cos t, i.e. tan t <= mu; otherwise the block
slides with F = mu N along -x'' (Coulomb's kinetic law):

    x'' = g (sin t - mu cos t).                                              (S)

Tipping. The floor's normal force acts at x_N (downhill of the point below G); the
moment balance about G, N x_N = F h, needs x_N = h F / N inside the base, x_N <= s/2.
At rest F / N = tan t; sliding, F / N = mu. Hence the block

    tips when tan t > s / (2h) and mu > s / (2h) (before it would slide),
    slides when tan t > mu and mu <= s / (2h),
    rests otherwise (tan t <= min(mu, s / (2h))).

No import of dominowave. Units: SI.
"""

from __future__ import annotations

import math

import numpy as np

G = 9.81  # standard gravity [m/s^2]


def incline_regime(t, mu, s, h):
    """ "rest", "slide" or "tip" for a block released at rest on an incline of angle ``t``
    [rad] with friction ``mu``, base length ``s`` [m] along the slope and centre of mass
    at height ``h`` [m] (module docstring; the boundaries themselves count as rest)."""
    tan_t, lever = math.tan(t), s / (2.0 * h)
    if tan_t > lever and mu > lever:
        return "tip"
    if tan_t > mu:
        return "slide"
    return "rest"


def incline_acceleration(t, mu, g=G):
    """Acceleration [m/s^2] down the slope of a block released at rest (eq S): g (sin t -
    mu cos t) when tan t > mu, else 0 (it sticks). Tipping is not checked here."""
    return g * (math.sin(t) - mu * math.cos(t)) if math.tan(t) > mu else 0.0


def incline_motion(t, mu, v0, times, g=G):
    """Position [m] and velocity [m/s] down the slope, shape (len(times),) each, of a
    block starting at x = 0 with velocity ``v0`` >= 0 [m/s] at time 0 (``times`` [s]).

    It moves with the kinetic acceleration (S) while v > 0; when tan t <= mu that
    acceleration is <= 0 and the block stops at t_stop = v0 / |a| and sticks there
    (static friction then holds it)."""
    times = np.asarray(times, dtype=float)
    a = g * (math.sin(t) - mu * math.cos(t))
    if v0 == 0.0 and math.tan(t) <= mu:
        return np.zeros_like(times), np.zeros_like(times)
    if a >= 0.0:
        return v0 * times + 0.5 * a * times**2, v0 + a * times
    t_stop = v0 / -a
    tc = np.minimum(times, t_stop)
    return v0 * tc + 0.5 * a * tc**2, v0 + a * tc


def incline_corner_forces(t, mu, s, h, m, g=G):
    """Normal forces [N] (downhill corner, uphill corner) of a block resting on two
    contact points at the ends of its base (a 2D box on an incline), and the friction
    force [N] holding it (or the kinetic friction while it slides).

    Statics: N_d + N_u = m g cos t, and the moment about G: (N_d - N_u) s / 2 = F h, with
    F = m g sin t sticking (tan t <= mu) or mu m g cos t sliding. Valid while both forces
    are >= 0 (the block does not tip: F h <= N s / 2)."""
    normal = m * g * math.cos(t)
    friction = m * g * math.sin(t) if math.tan(t) <= mu else mu * normal
    difference = 2.0 * friction * h / s
    if difference > normal:
        raise ValueError(f"t = {t} tips the block (needs min(tan t, mu) <= s / 2h = {s / (2 * h)})")
    return 0.5 * (normal + difference), 0.5 * (normal - difference), friction

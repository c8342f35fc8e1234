"""Dimensionless groups of the domino problem (paper section 2).

The package works in SI units internally; these helpers convert at the edges.

* ``k_star = m g / l`` -- the reference stiffness of Fig 4 and Fig 5B, defined in
  the paper by ``l / g = m / k*`` [N/m];
* ``v / sqrt(g l)`` -- McLachlan's scaling of the wave speed (eq 1);
* ``beta = asin(d / l)`` -- the inclination of a domino when it strikes the next
  one (Fig 1C) [rad].
"""

from __future__ import annotations

import numpy as np

from dominowave.checks import check_in_range, check_positive

__all__ = ["beta_from_spacing", "k_star", "spacing_from_beta", "speed_scale"]

G_STANDARD = 9.81
"""Gravitational acceleration used as the default everywhere [m/s^2]."""


def k_star(m, l, g=G_STANDARD):
    """Reference stiffness ``k* = m g / l`` [N/m] for mass ``m`` [kg], height ``l`` [m]."""
    check_positive("m", m)
    check_positive("l", l)
    check_positive("g", g)
    return np.asarray(m) * g / np.asarray(l)


def speed_scale(l, g=G_STANDARD):
    """McLachlan's speed scale ``sqrt(g l)`` [m/s] (eq 1)."""
    check_positive("l", l)
    check_positive("g", g)
    return np.sqrt(g * np.asarray(l))


def beta_from_spacing(d_over_l):
    """Collision angle ``beta = asin(d/l)`` [rad] for spacing ratio ``d/l`` in (0, 1)."""
    check_in_range("d_over_l", d_over_l, 0.0, 1.0)
    return np.arcsin(d_over_l)


def spacing_from_beta(beta):
    """Spacing ratio ``d/l = sin(beta)`` for ``beta`` in (0, pi/2) [rad]."""
    check_in_range("beta", beta, 0.0, np.pi / 2)
    return np.sin(beta)

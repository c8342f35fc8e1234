"""Single normal contacts between two bodies: Hertz's impact and the clipped spring-dashpot.

Two bodies approach along the contact normal with relative speed v [m/s]; m_r is their
reduced (effective) mass along that normal [kg] and delta the overlap [m]. Gravity is
absent during the contact. No import of dominowave. Units: SI.
"""

from __future__ import annotations

import math

from scipy.special import beta as beta_function


def hertz_collision(m_r, k, v):
    """Duration [s] and largest overlap [m] of an elastic impact with the Hertz force
    F = k delta^(3/2) (``k`` [N/m^1.5]), Johnson, Contact Mechanics (1985), sec. 11.4.

    Energy: (1/2) m_r v^2 = (1/2) m_r delta'^2 + (2/5) k delta^(5/2), so
    delta_max = (5 m_r v^2 / (4 k))^(2/5) and, with x = delta / delta_max,
    T = 2 (delta_max / v) int_0^1 dx / sqrt(1 - x^(5/2)) = (4/5) B(2/5, 1/2) delta_max / v,
    B Euler's beta function ((4/5) B(2/5, 1/2) = 2.94321...).
    """
    delta_max = (1.25 * m_r * v * v / k) ** 0.4
    return 0.8 * beta_function(0.4, 0.5) * delta_max / v, delta_max


def dashpot_restitution(zeta):
    """Coefficient of normal restitution of a linear spring-dashpot F = k delta + c delta'
    with damping ratio zeta = c / (2 sqrt(m_r k)) < 1/sqrt(2), the force clipped at zero
    (the dashpot never pulls): Schwager & Poeschel, Phys. Rev. E 75, 051304 (2007), eq. 20,

        e = exp(-zeta / sqrt(1 - zeta^2) (pi - atan(2 zeta sqrt(1 - zeta^2) / (1 - 2 zeta^2)))).

    The contact ends when the force, not the overlap, returns to zero, before the half
    period: e exceeds the textbook exp(-zeta pi / sqrt(1 - zeta^2)) of a pulling dashpot.
    """
    if not 0.0 <= zeta < math.sqrt(0.5):
        raise ValueError(f"zeta = {zeta} is outside the valid range [0, 1/sqrt(2))")
    root = math.sqrt(1.0 - zeta**2)
    phase = math.pi - math.atan(2.0 * zeta * root / (1.0 - 2.0 * zeta**2))
    return math.exp(-zeta / root * phase)

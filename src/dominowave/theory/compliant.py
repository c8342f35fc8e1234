"""Compliant dominoes: finite collision time, wave speed and P-wave bound (eqs 15-35).

The collision of domino ``n`` (point mass ``m`` at its tip, moving along ``xi``,
perpendicular to the domino) with the upright domino ``n+1`` (struck at height
``l cos(beta)``) is a linear spring between the masses ``m`` and
``m'' = m / cos^4(beta)`` (eq 29), so it lasts half a period of a spring-mass system
``T_c = pi sqrt(m_r / k_r)`` (eq 21) with ``m_r = m / (1 + cos^4 beta)`` (eq 30).

Stiffness conventions (``convention`` argument of every function taking ``k``):

* ``"paper"`` (default): ``k`` is the stiffness *of one particle*, ``k = pi R E``
  (eq 23); two particles in series give the contact spring ``k_r = k / 2``
  (eqs 22, 24). This is the ``k`` of eq 31 and of the paper's Fig 4
  (``k = k*, 1e4 k*, 1e8 k*``) and Fig 5B (``k*, 10 k*, 100 k*``).
* ``"contact"``: ``k`` is the contact spring itself, ``k_r = k`` -- YADE's linear law
  ``k_n = 2 E1 R1 E2 R2 / (E1 R1 + E2 R2)``, i.e. ``k_n = E R`` for equal spheres.

``k = inf`` is allowed everywhere and recovers the rigid EJ theory (``T_c = 0``).
All functions are vectorised; SI units in and out.
"""

from __future__ import annotations

from typing import Literal, get_args

import numpy as np

from dominowave.checks import check_nonnegative, check_positive
from dominowave.theory.rigid import check_beta, check_positive_finite, fall_time_limit
from dominowave.units import G_STANDARD

__all__ = [
    "StiffnessConvention",
    "collision_time",
    "collision_time_from_material",
    "contact_stiffness",
    "contact_stiffness_from_material",
    "p_wave_speed",
    "p_wave_speed_thick",
    "pair_regime_holds",
    "reduced_mass",
    "struck_effective_mass",
    "wave_speed",
    "wave_speed_thick",
]

StiffnessConvention = Literal["paper", "contact"]
"""``"paper"``: ``k`` per particle, ``k_r = k/2``; ``"contact"``: ``k_r = k`` (YADE)."""


def _check_convention(convention: str) -> str:
    if convention not in get_args(StiffnessConvention):
        raise ValueError(
            f"convention = {convention!r} is not one of {', '.join(get_args(StiffnessConvention))}"
        )
    return convention


def contact_stiffness(k, convention: StiffnessConvention = "paper"):
    """Contact spring ``k_r`` [N/m] from the stiffness ``k`` [N/m] (eqs 22, 24).

    ``"paper"``: ``k`` is one particle's stiffness, two in series: ``k_r = k/2``.
    ``"contact"``: ``k`` already is the contact spring: ``k_r = k``. ``k`` may be ``inf``.
    """
    check_positive("k", k)
    k = np.asarray(k, dtype=float)
    return k / 2.0 if _check_convention(convention) == "paper" else k  # eq. 22 with k1 = k2


def contact_stiffness_from_material(R, E, convention: StiffnessConvention = "paper"):
    """Contact spring ``k_r`` [N/m] of two equal spheres, radius ``R`` [m], modulus ``E`` [Pa].

    ``"paper"``: ``k_r = pi R E / 2`` (eqs 23-24). ``"contact"``: YADE's linear law
    ``k_n = 2 E1 R1 E2 R2 / (E1 R1 + E2 R2) = E R``.
    """
    R, E = check_positive_finite("R", R), check_positive_finite("E", E)
    if _check_convention(convention) == "paper":
        return np.pi * R * E / 2.0  # eq. 24
    return E * R


def struck_effective_mass(m, beta):
    """``m'' = m / cos^4(beta)`` [kg]: mass of domino n+1 seen along ``xi`` (eqs 26, 29)."""
    m = check_positive_finite("m", m)
    return m / np.cos(check_beta(beta)) ** 4  # eq. 29


def reduced_mass(m, beta):
    """Reduced mass ``m_r = m m'' / (m + m'') = m / (1 + cos^4 beta)`` [kg] (eq 30)."""
    m = check_positive_finite("m", m)
    return m / (1.0 + np.cos(check_beta(beta)) ** 4)  # eq. 30


def collision_time(k, m, beta, convention: StiffnessConvention = "paper"):
    """Collision time ``T_c = pi sqrt(m_r / k_r)`` [s] (eqs 21, 31).

    With the paper's convention this is eq 31, ``pi sqrt(2 m / (k (1 + cos^4 b)))``.
    ``k`` [N/m] in (0, inf], ``m`` [kg], ``beta`` [rad]; broadcast. ``k = inf`` gives 0.
    """
    k_r = contact_stiffness(k, convention)
    return np.pi * np.sqrt(reduced_mass(m, beta) / k_r)  # eq. 21 / 31


def collision_time_from_material(R, E, m, beta, convention: StiffnessConvention = "paper"):
    """Collision time [s] from sphere radius ``R`` [m] and Young's modulus ``E`` [Pa] (eq 32).

    Paper convention: ``T_c = sqrt(2 pi m / (R E (1 + cos^4 b)))`` = eq 31 with
    ``k = pi R E``. Contact convention: ``k_r = E R``.
    """
    k_r = contact_stiffness_from_material(R, E, convention)
    return collision_time(k_r, m, beta, convention="contact")  # eq. 32


def wave_speed(beta, l, m, k, g=G_STANDARD, convention: StiffnessConvention = "paper"):
    """Wave speed of compliant thin dominoes ``v = d / (T + T_c/2)`` [m/s] (eq 20).

    ``d = l sin(beta)``, ``T`` the EJ limit free-fall time (eq 13), ``T_c`` eq 31.
    Valid only in the pair-collision regime ``T > T_c / 2``: the value is returned
    everywhere; test validity with :func:`pair_regime_holds` (never hidden, see docs).
    ``v < (2/pi) v_w`` always (:func:`p_wave_speed`). ``k = inf`` gives the EJ speed.
    """
    beta = check_beta(beta)
    l = check_positive_finite("l", l)
    period = fall_time_limit(beta, l, g) + collision_time(k, m, beta, convention) / 2.0
    return l * np.sin(beta) / period  # eq. 20


def wave_speed_thick(beta, l, m, k, s, g=G_STANDARD, convention: StiffnessConvention = "paper"):
    """Wave speed of dominoes of thickness ``s`` [m]: ``v^s = (d + s) / (T + T_c/2)`` (eq 34).

    The free-fall time keeps its thin-domino value (the paper neglects the O((s/l)^2)
    change of the potential), so ``v^s / v = (d + s) / d`` exactly.
    """
    check_nonnegative("s", s)
    beta = check_beta(beta)
    d = check_positive_finite("l", l) * np.sin(beta)
    return wave_speed(beta, l, m, k, g, convention) * (d + s) / d  # eq. 34


def p_wave_speed(beta, l, m, k, convention: StiffnessConvention = "paper"):
    """P-wave speed ``v_w = d sqrt(k_r / m_r)`` [m/s] of the spring-mass chain (eq 33).

    Uses the same ``k_r`` and ``m_r`` as ``T_c``, hence ``v_w = pi d / T_c``; ``inf`` for
    ``k = inf``.
    """
    beta = check_beta(beta)
    d = check_positive_finite("l", l) * np.sin(beta)
    return d * np.sqrt(contact_stiffness(k, convention) / reduced_mass(m, beta))  # eq. 33


def p_wave_speed_thick(beta, l, m, k, s, convention: StiffnessConvention = "paper"):
    """P-wave speed of thick dominoes ``v_w^s = (d + s) sqrt(k_r / m_r)`` [m/s] (eq 35)."""
    check_nonnegative("s", s)
    beta = check_beta(beta)
    d = check_positive_finite("l", l) * np.sin(beta)
    return p_wave_speed(beta, l, m, k, convention) * (d + s) / d  # eq. 35


def pair_regime_holds(beta, l, m, k, g=G_STANDARD, convention: StiffnessConvention = "paper"):
    """Boolean mask: collisions are distinct pairs, ``T > T_c / 2`` (section 2.2).

    The contact of ``n`` on ``n+1`` starts ``T + T_c/2`` after the previous one started
    and must not begin before that one, of duration ``T_c``, has ended. Where the mask
    is False, eq 20 (and 33-37) are outside their range of validity.
    """
    t = fall_time_limit(beta, l, g)
    return t > collision_time(k, m, beta, convention) / 2.0

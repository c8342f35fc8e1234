"""Theory for a real (clump) domino: mapping the point-mass model onto the DEM domino.

The theory (section 2) treats a domino as a massless rod of height ``l`` with a
point mass ``m`` at its tip, pivoting about its foot: pivot inertia ``I = m l^2``,
gravity torque ``m g l sin(theta)``. A DEM domino is a column of spheres: mass
``m``, centre of mass at height ``h_cm``, pivot inertia ``I_A`` and, standing on a
sphere, a rolling pivot. Two mappings are offered:

* ``"point"`` -- the paper's usage: the theory with the domino's mass ``m`` and
  height ``l`` and the true ``g``, as if the mass sat at the tip.
* ``"clump"`` -- the rod keeps the collision geometry (the tip of domino ``n``
  strikes ``n+1`` at height ``l cos(beta)``: eqs 2-4 and 25-31 only use these lever
  arms), but with the clump's dynamics:

  - tip mass ``m_tip = I_A / l^2`` -- same pivot inertia, hence the same angular
    momentum balance (eq 2) and the same equivalent masses in the collision
    (``m`` and ``m / cos^4 beta`` in eq 29 become ``I_A / l^2`` and
    ``I_A / (l^2 cos^4 beta)``);
  - effective gravity ``g_eff = g m a l / I_A`` -- same free fall: the rod's
    ``theta'' = (g_eff / l) sin(theta)`` equals the clump's
    ``I_A theta'' = m g a sin(theta)``, where ``a`` is the distance from the centre
    of the base (pivot) sphere to the centre of mass: the base sphere rolls, so the
    centre of mass rises ``a (1 - cos(theta))`` over that sphere's centre
    (eqs 5, 10-14 with ``g -> g_eff``).

  ``I_A`` is taken about the floor contact point of the pivot sphere in the upright
  position (the rolling contact's instantaneous centre). The variation of the
  rolling inertia with angle, ``O(R/l)``, is neglected, like the thickness
  correction to the fall integral the paper neglects (section 2.3).

A box domino (``shape = "box"``) rolls on its rounded front bottom edge: ``a`` is the
distance from that edge's centre to the centre of mass, ``I_A`` the uniform cuboid's
inertia about the edge's floor contact, the same mapping otherwise; its pair spring is
``2 k_n`` (two contact points, ``ChainParams.pair_stiffness``).

For a uniform thin column ``I_A ~ m l^2 / 3`` and ``a ~ l / 2``: ``m_tip = m / 3``
and ``g_eff = 1.5 g``. Contacts use the DEM's springs directly (``convention=
"contact"``): ``k_r = n_across k_n`` (all columns of a 3D domino touch in parallel),
and the speed is the thickness-adjusted eq 34.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from dominowave import theory
from dominowave.chain.build import ChainParams, domino_box, domino_shape
from dominowave.units import beta_from_spacing

__all__ = [
    "EffectiveDomino",
    "Mapping",
    "effective_domino",
    "theory_collision_time",
    "theory_first_contacts",
    "theory_speed",
]

Mapping = Literal["point", "clump"]


@dataclass(frozen=True)
class EffectiveDomino:
    """Point-mass theory parameters for a DEM domino (see the module docstring).

    ``mass`` m [kg], ``com_height`` h_cm [m], ``arm`` a [m], ``inertia_pivot`` I_A
    [kg m^2], ``tip_mass`` [kg] and ``g_eff`` [m/s^2] to pass to ``dominowave.theory``
    as ``m`` and ``g`` together with the true ``l``.
    """

    mass: float
    com_height: float
    arm: float
    inertia_pivot: float
    tip_mass: float
    g_eff: float


def effective_domino(p: ChainParams, mapping: Mapping = "clump") -> EffectiveDomino:
    """Theory parameters of the domino of ``p`` under ``mapping`` ("point" or "clump")."""
    shape = domino_shape(p) if p.shape == "clump" else domino_box(p)
    m = shape.mass
    com = shape.centre_of_mass
    pc = shape.centres[shape.pivot] if p.shape == "clump" else shape.pivot_point
    arm = math.hypot(com[0] - pc[0], com[2] - pc[2])
    inertia = shape.inertia_about_y(shape.pivot_contact)
    if mapping == "point":
        return EffectiveDomino(m, float(com[2]), arm, inertia, m, p.g)
    if mapping == "clump":
        l = p.height
        return EffectiveDomino(
            m, float(com[2]), arm, inertia, inertia / l**2, p.g * m * arm * l / inertia
        )
    raise ValueError(f"mapping = {mapping!r} is not one of 'point', 'clump'")


def theory_collision_time(p: ChainParams, mapping: Mapping = "clump") -> float:
    """``T_c`` [s] (eq 31) with the contact spring ``k_n`` and the mapped tip mass."""
    eff = effective_domino(p, mapping)
    beta = beta_from_spacing(p.d_over_l)
    return float(theory.collision_time(p.pair_stiffness, eff.tip_mass, beta, "contact"))


def theory_speed(p: ChainParams, mapping: Mapping = "clump", rigid: bool = False) -> float:
    """Limit wave speed [m/s]: eq 34 ``(d + s) / (T + T_c / 2)``; ``rigid`` drops ``T_c``."""
    eff = effective_domino(p, mapping)
    beta = beta_from_spacing(p.d_over_l)
    k = math.inf if rigid else p.pair_stiffness
    return float(
        theory.wave_speed_thick(beta, p.height, eff.tip_mass, k, p.thickness, eff.g_eff, "contact")
    )


def theory_first_contacts(p: ChainParams, omega_1: float, mapping: Mapping = "clump") -> np.ndarray:
    """Transient first-contact times [s] of dominoes ``0..N-1``, shape ``(N,)``.

    Domino 0 is pushed at ``t = 0`` with angular velocity ``omega_1`` [rad/s]; the
    theory's effective start times ``t_n`` (eqs 8, 12, 19) are converted to the
    contact onsets ``t_n - T_c / 2`` for ``n >= 1`` (``theory.arrival_times``).
    """
    eff = effective_domino(p, mapping)
    beta = beta_from_spacing(p.d_over_l)
    t_c = theory_collision_time(p, mapping)
    t = theory.arrival_times(p.n_dominoes, omega_1, beta, p.height, eff.g_eff, t_c)
    t[1:] -= t_c / 2.0
    return t

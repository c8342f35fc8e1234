"""The properties of a contact between two materials (YADE's Ip2 functors).

A material gives a stiffness (Young's modulus E [Pa], or the contact stiffness k_n
[N/m] itself: the columns ``young`` and ``kn`` of MaterialTable, the other one nan), a
tangential-to-normal stiffness ratio, a friction coefficient and a restitution
(state.Material, MaterialTable).  A contact point between a body of
material a with rounding or sphere radius r_a and one of material b with r_b gets

* the stiffness of each side by the scene's rule (:func:`particle_stiffness`): the
  paper's ``pi r E`` (eq 23, RULE_PAPER), YADE's ``E r`` (RULE_YADE), or the k_n given
  (RULE_GIVEN); a wall takes the radius of the body touching it;
* the pair's normal and tangential stiffness (:func:`pair_stiffness`): the two sides in
  series (the paper's eq 22) or YADE's ``2 k_a k_b / (k_a + k_b)``
  (Ip2_FrictMat_FrictMat_FrictPhys);
* the pair's friction and restitution (:func:`pair_friction_restitution`): its own
  values where set (``Scene.set_pair``), else the smaller of the two materials'.

:func:`material_pair` gives all four; the sphere (contact.pair_properties) and box
(boxes.box_forces) drivers call it.  The Hertz law's modulus and radius are
laws/hertz.py.
"""

from __future__ import annotations

import math

from numba import njit

from dominowave.dem.compiled import inline_kernel

__all__ = [
    "RULE_GIVEN",
    "RULE_PAPER",
    "RULE_YADE",
    "material_pair",
    "pair_friction_restitution",
    "pair_stiffness",
    "particle_stiffness",
]

# the rule that turns the materials' stiffness into a contact's k_n (MaterialTable.rule)
RULE_PAPER = 0  # Young's moduli, the paper's pi R E per particle in series
RULE_YADE = 1  # Young's moduli, YADE's E R per particle
RULE_GIVEN = 2  # contact stiffnesses k_n given per material


@njit(cache=True, error_model="numpy")
def particle_stiffness(young, kn, radius, rule):
    """Stiffness of one particle [N/m] of radius [m] whose material gives ``young`` (E
    [Pa]) or ``kn`` (k_n [N/m]; the other is nan): pi R E (RULE_PAPER, eq. 23), E R
    (RULE_YADE) or the k_n given (RULE_GIVEN)."""
    if rule == RULE_GIVEN:
        return kn
    if rule == RULE_PAPER:
        return math.pi * radius * young
    return young * radius


@njit(cache=True, error_model="numpy")
def pair_stiffness(k1, k2, rule):
    """Contact stiffness of two particles [N/m].

    RULE_PAPER: springs in series ``k1 k2 / (k1 + k2)`` (eq. 22; equal spheres: pi R E / 2,
    eq. 24); RULE_YADE and RULE_GIVEN: ``2 k1 k2 / (k1 + k2)``
    (Ip2_FrictMat_FrictMat_FrictPhys; equal given k_n: that k_n).
    """
    if k1 <= 0.0 or k2 <= 0.0:
        return 0.0
    series = k1 * k2 / (k1 + k2)
    if rule == RULE_PAPER:
        return series
    return 2.0 * series


@inline_kernel()
def pair_friction_restitution(mats, m1, m2):
    """Friction coefficient and restitution of a contact between materials m1 and m2.

    The pair's own values where set (``Scene.set_pair``, e.g. domino-domino apart from
    domino-floor), otherwise the min rule ``min(mu_1, mu_2)`` (paper, section 3) and
    ``min(e_1, e_2)``; a table entry of nan means "not set".
    """
    mu = mats.pair_friction[m1, m2]
    if math.isnan(mu):
        mu = min(mats.friction[m1], mats.friction[m2])
    e = mats.pair_restitution[m1, m2]
    if math.isnan(e):
        e = min(mats.restitution[m1], mats.restitution[m2])
    return mu, e


@inline_kernel()
def material_pair(mats, ma, ra, mb, rb, out):
    """kn, kt, mu, restitution of a linear contact point of a body of material ``ma`` and
    rounding (or sphere) radius ``ra`` [m] with one of ``mb``, ``rb`` into ``out[0:4]``:
    stiffnesses by the scene's rule (:func:`particle_stiffness`,
    :func:`pair_stiffness`), friction and restitution of the material pair
    (:func:`pair_friction_restitution`)."""
    rule = mats.rule[0]
    ka = particle_stiffness(mats.young[ma], mats.kn[ma], ra, rule)
    kb = particle_stiffness(mats.young[mb], mats.kn[mb], rb, rule)
    out[0] = pair_stiffness(ka, kb, rule)
    out[1] = pair_stiffness(ka * mats.kt_ratio[ma], kb * mats.kt_ratio[mb], rule)
    out[2], out[3] = pair_friction_restitution(mats, ma, mb)

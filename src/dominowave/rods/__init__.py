"""The paper's hinged compliant-domino model, simulated with Newton's laws.

A reduced model: one angle per domino about its base hinge, compliant contacts between
neighbours (linear or Hertzian, optional dashpot and friction, geometric or head-on
normal), gravity throughout, a floor. It contains no collision rule and no collision
time of the theory; :mod:`dominowave.chain.theory_vs_rods` compares the two.
"""

from dominowave.rods.measure import Collisions, first_collisions, struck_omega
from dominowave.rods.model import (
    CONTACT_LAWS,
    NORMALS,
    MassDistribution,
    RodChain,
    block,
    custom_mass,
    point_mass,
    thin_rod,
)
from dominowave.rods.simulate import RodRun, RodStepper, simulate

__all__ = [
    "CONTACT_LAWS",
    "NORMALS",
    "Collisions",
    "MassDistribution",
    "RodChain",
    "RodRun",
    "RodStepper",
    "block",
    "custom_mass",
    "first_collisions",
    "point_mass",
    "simulate",
    "struck_omega",
    "thin_rod",
]

"""Physical parameters of the theory and rods scenarios, in the vocabulary of ChainParams.

The three scenario kinds describe the same chain of dominoes, so they use the same names
(:class:`~dominowave.chain.build.ChainParams` is the reference): ``height`` l,
``thickness`` s, the spacing ratio ``d_over_l`` (d = clear gap between faces, the pitch is
``d + s``), ``g``, ``n_dominoes``, ``stiffness_ratio`` (the paper's k/k*),
``friction_floor`` / ``friction_dominoes``. Their default domino is the chain's:
l = 50 mm, s = 5 mm at d/l = 0.4, of the chain's mass (ten 5 mm beads at 1000 kg/m^3,
0.65 g), so a default theory, rods and chain run describe one domino. What differs, and
why:

* ``mass`` [kg] is given here; the chain's domino is a clump of beads whose mass follows
  from their ``density``.
* ``thickness`` may be 0 here (the paper's thin dominoes, eqs 2-33) and up to ``height``;
  the chain's beads need ``0 < s < l/2``.
* ``stiffness`` [N/m] is the paper's per-particle k (the contact spring is k/2, eq 24);
  the chain gives the contact spring ``kn`` itself, or ``young``.
* the theory's default is the rigid limit (``stiffness = inf``, eq 14), the limit the
  paper's formulas start from; rods and chain default to k/k* = 1e4.

Each field is declared once with :func:`dominowave.params.parameter` (default, unit,
description, range); :mod:`dominowave.io.models` derives the study schema from these
declarations, as it does for ChainParams.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from dominowave.chain.build import ChainParams
from dominowave.params import check_parameters, choice, parameter

__all__ = ["HingedChainParams", "RodsParams", "TheoryParams"]

StiffnessConvention = Literal["paper", "contact"]
MassModel = Literal["point", "rod", "block"]
ContactNormal = Literal["geometric", "head-on"]

_CHAIN = ChainParams()
"""The chain's default domino, the default of every scenario kind."""


@dataclass(frozen=True)
class HingedChainParams:
    """A chain of identical dominoes turning about their front bottom edges (SI units).

    The contact stiffness is given once: ``stiffness`` [N/m] (k per particle) or
    ``stiffness_ratio`` (k/k* with k* = m g / l, Fig 4); the other is None.
    """

    n_dominoes: int = parameter(_CHAIN.n_dominoes, "", "number of dominoes", ge=2, le=100_000)
    height: float = parameter(_CHAIN.height, "m", "domino height l", gt=0)
    thickness: float = parameter(
        _CHAIN.thickness, "m", "domino thickness s (eq 34; 0 = thin dominoes)", ge=0
    )
    d_over_l: float = parameter(
        _CHAIN.d_over_l, "", "spacing ratio d/l (d = clear gap, pitch d + s)", gt=0, lt=1
    )
    mass: float = parameter(_CHAIN.mass, "kg", "domino mass m", gt=0)
    g: float = parameter(_CHAIN.g, "m/s^2", "gravitational acceleration", gt=0)
    stiffness: float | None = parameter(
        math.inf,
        "N/m",
        "contact stiffness k per particle (inf = rigid dominoes, eq 14)",
        gt=0,
        allow_inf=True,
    )
    stiffness_ratio: float | None = parameter(
        None, "", "contact stiffness as k / k* with k* = m g / l (Fig 4); replaces stiffness", gt=0
    )

    def __post_init__(self):
        check_parameters(self)
        if self.thickness >= self.height:
            raise ValueError(
                f"thickness = {self.thickness!r} m must be less than height = {self.height!r} m"
            )
        if (self.stiffness is None) == (self.stiffness_ratio is None):
            raise ValueError(
                f"stiffness = {self.stiffness!r} and stiffness_ratio = {self.stiffness_ratio!r}:"
                " give exactly one of them"
            )

    @property
    def spacing(self) -> float:
        """Clear gap ``d`` between neighbouring dominoes [m]."""
        return self.d_over_l * self.height


@dataclass(frozen=True)
class TheoryParams(HingedChainParams):
    """The chain the closed-form theory describes (eqs 2-42)."""

    stiffness_convention: StiffnessConvention = choice(
        StiffnessConvention,
        "paper: k per particle, contact spring k_r = k/2 (eqs 22-24); contact: k_r = k (YADE)",
    )
    friction_floor: float = parameter(
        0.3, "", "domino-floor friction coefficient mu (eqs 38-42)", ge=0
    )


@dataclass(frozen=True)
class RodsParams(HingedChainParams):
    """The hinged compliant dominoes of :mod:`dominowave.rods` (the paper's model, simulated)."""

    stiffness: float | None = parameter(
        None, "N/m", "contact stiffness k per particle; the contact spring is k/2 (eq 24)", gt=0
    )
    stiffness_ratio: float | None = parameter(
        1e4, "", "contact stiffness as k / k* with k* = m g / l (Fig 4); replaces stiffness", gt=0
    )
    mass_model: MassModel = choice(
        MassModel, "mass distribution: point mass at the tip (the paper's), thin rod, block"
    )
    normal: ContactNormal = choice(
        ContactNormal, "contact normal: from the geometry, or head-on as in the theory"
    )
    damping_ratio: float = parameter(
        0.0, "", "dashpot damping ratio zeta of a contact (0 = elastic)", ge=0, lt=1
    )
    friction_dominoes: float = parameter(
        0.0, "", "Coulomb friction between dominoes (needs normal = geometric)", ge=0
    )
    restitution_floor: float = parameter(
        0.0, "", "restitution of a domino hitting the floor", ge=0, le=1
    )

    def __post_init__(self):
        super().__post_init__()
        if self.friction_dominoes > 0 and self.normal != "geometric":
            # the head-on force of the theory is frictionless (rods.RodChain refuses it too)
            raise ValueError(
                f"friction_dominoes = {self.friction_dominoes!r} needs normal = 'geometric'"
                f" (normal = {self.normal!r} is the theory's frictionless head-on force)"
            )

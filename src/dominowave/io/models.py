"""Config models of the scenarios a study can run (SI units, every field documented).

Each model registers itself under its ``kind``; the matching run function is in
:mod:`dominowave.sweep.scenarios`. Defaults describe a standard domino
(48 mm tall, 7.5 mm thick, 8 g) at spacing ``d/l = 0.5``.
"""

from __future__ import annotations

import math
from typing import ClassVar, Literal

import numpy as np
from pydantic import model_validator

from dominowave.io.schema import ScenarioModel, quantity, register_scenario_model
from dominowave.units import G_STANDARD, k_star

__all__ = ["ChainScenario", "DominoChainBase", "RodsScenario", "TheoryScenario"]


class DominoChainBase(ScenarioModel):
    """Fields shared by every domino-chain scenario (not registered itself).

    The contact stiffness is given once: ``stiffness`` [N/m] or ``stiffness_ratio``
    (k/k*); giving one unsets the other's default. Both follow the paper's
    convention unless a scenario says otherwise: ``k`` per particle, the contact
    spring is ``k_r = k/2`` (eqs 22-24).
    """

    height: float = quantity(0.048, "m", "domino height l", gt=0)
    thickness: float = quantity(0.0075, "m", "domino thickness s (eq 34)", ge=0)
    spacing: float = quantity(
        0.024, "m", "gap d between neighbouring dominoes (pitch is d + s)", gt=0
    )
    mass: float = quantity(0.008, "kg", "domino mass m", gt=0)
    gravity: float = quantity(G_STANDARD, "m/s^2", "gravitational acceleration g", gt=0)
    n_dominoes: int = quantity(30, "", "number of dominoes in the chain", ge=2, le=100_000)
    stiffness: float | None = quantity(
        math.inf,
        "N/m",
        "contact stiffness k per particle (inf = rigid dominoes, eq 14)",
        gt=0,
        allow_inf_nan=True,
    )
    stiffness_ratio: float | None = quantity(
        None, "", "contact stiffness as k / k* with k* = m g / l (Fig 4); replaces stiffness", gt=0
    )
    push_omega: float = quantity(
        5.0, "rad/s", "angular velocity Omega_1 given to the first domino", gt=0
    )

    ALTERNATIVES: ClassVar = (("stiffness", "stiffness_ratio"),)
    """Groups of fields that give the same quantity: giving one unsets the others."""

    @model_validator(mode="before")
    @classmethod
    def _given_field_unsets_its_alternatives(cls, data):
        if isinstance(data, dict):
            for group in cls.ALTERNATIVES:
                given = [k for k in group if k in data]
                if len(given) == 1:
                    data = {**data, **{k: None for k in group if k != given[0]}}
        return data

    @model_validator(mode="after")
    def _geometry(self):
        if self.spacing >= self.height:
            raise ValueError(
                f"spacing = {self.spacing!r} m must be less than height = {self.height!r} m"
                " (d/l in (0, 1): otherwise a falling domino misses the next one)"
            )
        if self.thickness >= self.height:
            raise ValueError(
                f"thickness = {self.thickness!r} m must be less than height = {self.height!r} m"
            )
        if (self.stiffness is None) == (self.stiffness_ratio is None):
            raise ValueError(
                f"stiffness = {self.stiffness!r} and stiffness_ratio = {self.stiffness_ratio!r}:"
                " give exactly one of them"
            )
        return self

    @property
    def d_over_l(self) -> float:
        """Spacing ratio d/l [-]."""
        return self.spacing / self.height

    @property
    def k_star(self) -> float:
        """Reference stiffness k* = m g / l [N/m]."""
        return float(k_star(self.mass, self.height, self.gravity))

    @property
    def contact_stiffness(self) -> float:
        """Contact stiffness k [N/m], from ``stiffness`` or ``stiffness_ratio * k*``."""
        if self.stiffness_ratio is None:
            return self.stiffness
        return self.stiffness_ratio * self.k_star

    @property
    def speed_scale(self) -> float:
        """McLachlan's speed scale sqrt(g l) [m/s] (eq 1)."""
        return math.sqrt(self.gravity * self.height)

    def theory_speed(self, d_over_l):
        """Theory wave speed v^s [m/s] (eq 34) of these dominoes at spacing ``d_over_l``."""
        from dominowave import theory

        beta = np.arcsin(np.asarray(d_over_l, dtype=float))
        k, conv = self.contact_stiffness, getattr(self, "stiffness_convention", "paper")
        return theory.wave_speed_thick(
            beta, self.height, self.mass, k, self.thickness, self.gravity, conv
        )

    def theory_valid(self, d_over_l):
        """Where eq 20/34 applies: distinct pair collisions, ``T > T_c / 2`` (section 2.2)."""
        from dominowave import theory

        beta = np.arcsin(np.asarray(d_over_l, dtype=float))
        k, conv = self.contact_stiffness, getattr(self, "stiffness_convention", "paper")
        return theory.pair_regime_holds(beta, self.height, self.mass, k, self.gravity, conv)


@register_scenario_model
class TheoryScenario(DominoChainBase):
    """Closed-form wave of the paper (EJ rigid limit + finite collision time, eqs 2-42)."""

    kind: Literal["theory"] = "theory"
    RECORDS_FRAMES: ClassVar = True
    stiffness_convention: Literal["paper", "contact"] = quantity(
        "paper",
        "",
        "paper: k per particle, contact spring k_r = k/2 (eqs 22-24); contact: k_r = k (YADE)",
    )
    friction: float = quantity(0.3, "", "domino-foundation friction coefficient mu", ge=0)
    n_frames: int = quantity(
        200, "", "frames of the drawn trajectory (kinematics for `animate`)", ge=2, le=100_000
    )

    @classmethod
    def example_grid(cls) -> dict[str, list]:
        return {"spacing": [0.012, 0.024, 0.036], "stiffness_ratio": [100.0, 1e4]}


@register_scenario_model
class RodsScenario(DominoChainBase):
    """Hinged compliant dominoes simulated with Newton's laws (dominowave.rods, issue 5)."""

    kind: Literal["rods"] = "rods"
    RECORDS_FRAMES: ClassVar = True  # interval: dominowave.sweep.run_rods.frame_schedule
    stiffness: float | None = quantity(
        None, "N/m", "contact stiffness k per particle; the contact spring is k/2 (eq 24)", gt=0
    )
    stiffness_ratio: float | None = quantity(
        1e4, "", "contact stiffness as k / k* with k* = m g / l (Fig 4); replaces stiffness", gt=0
    )
    mass_model: Literal["point", "rod", "block"] = quantity(
        "point", "", "mass distribution: point mass at the tip (the paper's), thin rod, block"
    )
    normal: Literal["geometric", "head-on"] = quantity(
        "geometric", "", "contact normal: from the geometry, or head-on as in the theory"
    )
    damping_ratio: float = quantity(
        0.0, "", "dashpot damping ratio zeta of a contact (0 = elastic)", ge=0, lt=1
    )
    contact_friction: float = quantity(
        0.0, "", "Coulomb friction between dominoes (needs normal = geometric)", ge=0
    )
    floor_restitution: float = quantity(
        0.0, "", "restitution of a domino hitting the floor", ge=0, le=1
    )
    steps_per_contact: float = quantity(
        50.0, "", "time steps per shortest possible contact (>= 50 is standard)", ge=20
    )

    @classmethod
    def example_grid(cls) -> dict[str, list]:
        return {"spacing": [0.012, 0.024, 0.036], "stiffness_ratio": [1e3, 1e4]}


@register_scenario_model
class ChainScenario(ScenarioModel):
    """DEM chain of sphere clumps (dominowave.chain on dominowave.dem, paper section 3).

    The fields are those of :class:`dominowave.chain.build.ChainParams` (same names,
    same defaults, validated by it) plus how the run is driven.
    """

    kind: Literal["chain"] = "chain"
    RECORDS_FRAMES: ClassVar = True
    ALTERNATIVES: ClassVar = (("stiffness_ratio", "kn", "young"),)

    n_dominoes: int = quantity(30, "", "number of dominoes", ge=2, le=100_000)
    height: float = quantity(0.05, "m", "domino height l", gt=0)
    thickness: float = quantity(0.005, "m", "domino thickness s = sphere diameter", gt=0)
    width: float = quantity(0.025, "m", "domino width (3D model)", gt=0)
    d_over_l: float = quantity(0.4, "", "spacing ratio d/l (d = clear gap)", gt=0, lt=1)
    density: float = quantity(1000.0, "kg/m^3", "bead density", gt=0)
    stiffness_ratio: float | None = quantity(
        1e4, "", "paper's k/k* (k per particle, contact spring k_n = k/2); or kn, or young", gt=0
    )
    kn: float | None = quantity(None, "N/m", "contact spring k_n, directly", gt=0)
    young: float | None = quantity(None, "Pa", "Young's modulus (with young_rule)", gt=0)
    young_rule: Literal["paper", "yade"] = quantity(
        "paper", "", "k_n from young: paper pi R E / 2 (eq 24) or yade E R"
    )
    kt_ratio: float = quantity(1.0, "", "tangential / normal contact stiffness", gt=0)
    shear_kinematics: Literal["contact_point", "yade"] = quantity(
        "contact_point", "", "shear rate: contact_point (material points) or yade (YADE's)"
    )
    friction_dominoes: float = quantity(0.0, "", "friction between dominoes phi_d", ge=0)
    friction_floor: float = quantity(0.3, "", "friction with the floor phi_f", ge=0)
    damping: float = quantity(0.0, "", "local (YADE-style) damping", ge=0, lt=1)
    restitution: float | None = quantity(
        None, "", "normal restitution (not set = elastic)", gt=0, le=1
    )
    model: Literal["2d", "3d"] = quantity("2d", "", "2d: xz plane only; 3d: free")
    spheres_per_column: int | None = quantity(
        None, "", "spheres per column (not set: round(l/s), touching)", ge=2
    )
    base: Literal["one", "two"] = quantity("one", "", "one bottom sphere, or two half-size")
    held: bool = quantity(True, "", "untouched dominoes are held until first touched")
    lateral_asymmetry: float = quantity(0.0, "rad", "random yaw amplitude (3d)", ge=0, lt=0.1)
    asymmetry_seed: int = quantity(0, "", "seed of the lateral asymmetry", ge=0)
    g: float = quantity(G_STANDARD, "m/s^2", "gravitational acceleration", gt=0)
    push_omega: float | None = quantity(
        None, "rad/s", "push of domino 0 about its base (not set: sqrt(g/l))", gt=0
    )
    steps_per_collision: int = quantity(
        50, "", "time steps per theory collision time T_c (sets dt)", ge=10
    )

    @model_validator(mode="before")
    @classmethod
    def _given_field_unsets_its_alternatives(cls, data):
        return DominoChainBase._given_field_unsets_its_alternatives.__func__(cls, data)

    @model_validator(mode="after")
    def _valid_chain(self):
        if sum(x is not None for x in (self.stiffness_ratio, self.kn, self.young)) != 1:
            raise ValueError(
                f"stiffness_ratio = {self.stiffness_ratio!r}, kn = {self.kn!r},"
                f" young = {self.young!r}: give exactly one of them"
            )
        from dominowave.chain.scenario import DominoChain

        # ChainParams checks the rest (e.g. thickness < height / 2), DominoChain that the
        # DEM can resolve the stiffness and hold the run (so `config` refuses what `run`
        # would), at no cost: nothing is simulated or allocated
        DominoChain(self.params(), steps_per_collision=self.steps_per_collision)
        return self

    _RUN_FIELDS: ClassVar = ("kind", "push_omega", "steps_per_collision")

    def params(self, **changes):
        """The :class:`~dominowave.chain.build.ChainParams` of this config."""
        from dominowave.chain.build import ChainParams

        fields = {k: v for k, v in self if k not in self._RUN_FIELDS}
        return ChainParams(**{**fields, **changes})

    @property
    def seed(self) -> int:
        return self.asymmetry_seed

    @property
    def speed_scale(self) -> float:
        return math.sqrt(self.g * self.height)

    def theory_speed(self, d_over_l):
        """The chain's theory speed [m/s] (eq 34, ``chain.compare`` clump mapping)."""
        from dominowave.chain.compare import theory_speed

        values = np.atleast_1d(np.asarray(d_over_l, dtype=float))
        out = np.array([theory_speed(self.params(d_over_l=float(x))) for x in values])
        return out.reshape(np.shape(d_over_l))

    def theory_valid(self, d_over_l):
        """Where the theory applies (not decided for the clump mapping: everywhere)."""
        return np.ones(np.shape(d_over_l), dtype=bool)

    @classmethod
    def example_grid(cls) -> dict[str, list]:
        return {"d_over_l": [0.3, 0.5, 0.7], "stiffness_ratio": [1e3, 1e4]}

"""Config models of the scenarios a study can run (SI units, every field documented).

The registry of kinds (:data:`dominowave.io.kinds.KINDS`) names each model with its run
function. Each model's physical fields are derived from its scenario's parameter class
(:class:`~dominowave.chain.ChainParams`, :class:`~dominowave.chain.params.TheoryParams`,
:class:`~dominowave.chain.params.RodsParams`): one vocabulary and one default domino
(50 mm tall, 5 mm thick, at ``d/l = 0.4``) for every kind.
"""

from __future__ import annotations

import math
from typing import ClassVar, Literal

import numpy as np
from pydantic import create_model, model_validator

from dominowave.chain.build import ChainParams
from dominowave.chain.fidelity import check_fidelity
from dominowave.chain.params import RodsParams, TheoryParams
from dominowave.chain.settings import ChainSettings, numerics
from dominowave.io.schema import ScenarioModel, fields_from_parameters, quantity
from dominowave.params import parameter_specs
from dominowave.units import k_star

__all__ = ["ChainScenario", "RodsScenario", "TheoryScenario"]


class _HingedRun(ScenarioModel):
    """What the theory and rods scenarios share besides their physical fields (which are
    added from :class:`~dominowave.chain.params.TheoryParams` / ``RodsParams``): the push,
    the stiffness alternatives and the quantities derived from the fields.

    The contact stiffness is given once: ``stiffness`` [N/m] or ``stiffness_ratio``
    (k/k*); giving one unsets the other's default. Both follow the paper's
    convention unless a scenario says otherwise: ``k`` per particle, the contact
    spring is ``k_r = k/2`` (eqs 22-24).
    """

    PARAMS: ClassVar[type]
    """The parameter dataclass the physical fields are derived from."""
    RECORDS_FRAMES: ClassVar = True
    """Both kinds record frames of the dominoes' angles (the rods at the interval of
    :func:`dominowave.sweep.run_rods.frame_schedule`)."""
    EXAMPLE_STIFFNESS_RATIOS: ClassVar[tuple[float, ...]]
    """The stiffness ratios k/k* of the kind's example sweep (:meth:`example_grid`)."""
    ALTERNATIVES: ClassVar = (("stiffness", "stiffness_ratio"),)
    """Groups of fields that give the same quantity: giving one unsets the others."""
    RENAMED: ClassVar = {
        "spacing": "d_over_l (the spacing ratio d/l = spacing / height)",
        "gravity": "g",
    }

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
    def _valid_params(self):
        self.params()  # the parameter class checks the rules that join fields
        return self

    def params(self, **changes):
        """The parameter dataclass (``PARAMS``) of this config."""
        fields = {name: getattr(self, name) for name in parameter_specs(self.PARAMS)}
        return self.PARAMS(**{**fields, **changes})

    @property
    def spacing(self) -> float:
        """Clear gap ``d`` between neighbouring dominoes [m]."""
        return self.d_over_l * self.height

    @property
    def k_star(self) -> float:
        """Reference stiffness k* = m g / l [N/m]."""
        return float(k_star(self.mass, self.height, self.g))

    @property
    def contact_stiffness(self) -> float:
        """Contact stiffness k [N/m], from ``stiffness`` or ``stiffness_ratio * k*``."""
        if self.stiffness_ratio is None:
            return self.stiffness
        return self.stiffness_ratio * self.k_star

    @property
    def speed_scale(self) -> float:
        """McLachlan's speed scale sqrt(g l) [m/s] (eq 1)."""
        return math.sqrt(self.g * self.height)

    def theory_speed(self, d_over_l):
        """Theory wave speed v^s [m/s] (eq 34) of these dominoes at spacing ``d_over_l``."""
        from dominowave import theory

        beta = np.arcsin(np.asarray(d_over_l, dtype=float))
        k, conv = self.contact_stiffness, getattr(self, "stiffness_convention", "paper")
        return theory.wave_speed_thick(
            beta, self.height, self.mass, k, self.thickness, self.g, conv
        )

    def theory_valid(self, d_over_l):
        """Where eq 20/34 applies: distinct pair collisions, ``T > T_c / 2`` (section 2.2)."""
        from dominowave import theory

        beta = np.arcsin(np.asarray(d_over_l, dtype=float))
        k, conv = self.contact_stiffness, getattr(self, "stiffness_convention", "paper")
        return theory.pair_regime_holds(beta, self.height, self.mass, k, self.g, conv)

    @classmethod
    def example_grid(cls) -> dict[str, list]:
        """The example sweep: three spacing ratios d/l by the kind's stiffness ratios k/k*."""
        return {"d_over_l": [0.2, 0.4, 0.6], "stiffness_ratio": list(cls.EXAMPLE_STIFFNESS_RATIOS)}


_PUSH_OMEGA = (
    float,
    quantity(5.0, "rad/s", "angular velocity Omega_1 given to the first domino", gt=0),
)


def _hinged_scenario(name: str, base: type[_HingedRun], summary: str, **run_fields):
    """The study model ``name`` of a hinged-chain kind (theory, rods).

    Its fields: the physical ones, derived from ``base.PARAMS`` (names, defaults, SI units,
    ranges), the push ``push_omega`` [rad/s], and ``run_fields`` (``name=(type, quantity)``:
    how the kind's run is driven). Its docstring: ``summary``, then where the fields come
    from.
    """
    params = base.PARAMS
    extra = " and ".join(f"``{field}``" for field in ("push_omega", *run_fields))
    return create_model(
        name,
        __base__=base,
        __doc__=(
            f"{summary}\n\nThe physical fields are those of"
            f" :class:`{params.__module__}.{params.__qualname__}` (names, defaults, units,"
            f" ranges), plus {extra}."
        ),
        __module__=__name__,
        **fields_from_parameters(params),
        push_omega=_PUSH_OMEGA,
        **run_fields,
    )


class _TheoryRun(_HingedRun):
    kind: Literal["theory"] = "theory"
    PARAMS: ClassVar = TheoryParams
    RENAMED: ClassVar = {**_HingedRun.RENAMED, "friction": "friction_floor"}
    EXAMPLE_STIFFNESS_RATIOS: ClassVar = (100.0, 1e4)


TheoryScenario = _hinged_scenario(
    "TheoryScenario",
    _TheoryRun,
    "Closed-form wave of the paper (EJ rigid limit + finite collision time, eqs 2-42).",
    n_frames=(
        int,
        quantity(
            200,
            "",
            "frames of the drawn trajectory (kinematics for `animate`)",
            ge=2,
            le=100_000,
        ),
    ),
)


class _RodsRun(_HingedRun):
    kind: Literal["rods"] = "rods"
    PARAMS: ClassVar = RodsParams
    RENAMED: ClassVar = {
        **_HingedRun.RENAMED,
        "contact_friction": "friction_dominoes",
        "floor_restitution": "restitution_floor",
    }
    EXAMPLE_STIFFNESS_RATIOS: ClassVar = (1e3, 1e4)


RodsScenario = _hinged_scenario(
    "RodsScenario",
    _RodsRun,
    "Hinged compliant dominoes simulated with Newton's laws (dominowave.rods).",
    steps_per_contact=(
        float,
        quantity(50.0, "", "time steps per shortest possible contact (>= 50 is standard)", ge=20),
    ),
)


class _ChainRun(ScenarioModel):
    """How a DEM chain run is driven; the physical fields are added from ``ChainParams``."""

    kind: Literal["chain"] = "chain"
    RECORDS_FRAMES: ClassVar = True
    ALTERNATIVES: ClassVar = (("stiffness_ratio", "kn", "young"),)

    PRESET_FIELDS: ClassVar = (
        "shape",
        "height",
        "thickness",
        "width",
        "d_over_l",
        "density",
        "young",
        "young_rule",
        "friction_dominoes",
        "friction_floor",
        "restitution_dominoes",
        "restitution_floor",
    )
    """The fields a ``preset`` sets from the material data (``standard_domino``)."""

    @model_validator(mode="before")
    @classmethod
    def _given_field_unsets_its_alternatives(cls, data):
        if isinstance(data, dict) and "fidelity" in data:  # (one line, before pydantic's
            check_fidelity(data["fidelity"])  # two on the union's members)
        data = cls._expand_preset(data)
        return _HingedRun._given_field_unsets_its_alternatives.__func__(cls, data)

    @classmethod
    def _expand_preset(cls, data):
        """``preset = "standard"`` with ``gap`` and ``floor``: the fields of
        :func:`dominowave.chain.presets.standard_domino` (``model`` may be given; a field the
        preset sets may be given only with the preset's own value, as in a stored config)."""
        if not isinstance(data, dict) or data.get("preset") is None:
            if isinstance(data, dict) and (data.get("gap") is not None or data.get("floor")):
                raise ValueError("gap and floor are the options of a preset: give preset too")
            return data
        if data["preset"] != "standard":
            raise ValueError(f"preset = {data['preset']!r} is not one of 'standard'")
        if data.get("gap") is None or data.get("floor") is None:
            raise ValueError("preset = 'standard' needs gap [m] and floor (felt, glass, ...)")
        # read before the fields are validated: refuse a wrong type here, naming the key
        gap, floor = data["gap"], data["floor"]
        if isinstance(gap, bool) or not isinstance(gap, int | float):
            raise ValueError(f"gap = {gap!r} is not a number: write the clear gap in m")
        if not isinstance(floor, str):
            raise ValueError(f"floor = {floor!r} is not text: write a floor's name, e.g. 'felt'")
        from dominowave.chain.presets import standard_domino

        extra = {"model": data["model"]} if "model" in data else {}
        if "n_dominoes" in data:
            extra["n_dominoes"] = data["n_dominoes"]
        params = standard_domino(gap=data["gap"], floor=data["floor"], **extra)
        filled = {"model": params.model, **data}
        for name in cls.PRESET_FIELDS:
            value = getattr(params, name)
            if name in data and data[name] is not None and data[name] != value:
                raise ValueError(
                    f"{name} = {data[name]!r} is set by preset = 'standard' (to {value!r});"
                    " leave it out"
                )
            filled[name] = value
        for name in ("stiffness_ratio", "kn"):
            if data.get(name) is not None:
                raise ValueError(f"{name} = {data[name]!r}: preset = 'standard' sets young")
        return filled

    @model_validator(mode="after")
    def _valid_chain(self):
        if sum(x is not None for x in (self.stiffness_ratio, self.kn, self.young)) > 1:
            raise ValueError(
                f"stiffness_ratio = {self.stiffness_ratio!r}, kn = {self.kn!r},"
                f" young = {self.young!r}: give at most one of them"
            )
        from dominowave.chain.scenario import DominoChain

        # ChainParams checks the rest (e.g. thickness < height / 2), DominoChain that the
        # DEM can resolve the stiffness and hold the run (so `config` refuses what `run`
        # would), at no cost: nothing is simulated or allocated
        DominoChain(self.params(), **self.run_options())
        if self.fit_from is not None:
            from dominowave.chain.wave import check_fit_from

            check_fit_from(self.fit_from, self.n_dominoes)
        return self

    def run_options(self) -> dict:
        """The settings of the run that :class:`~dominowave.chain.scenario.DominoChain`
        takes besides the parameters: ``steps_per_collision`` and the numerics of
        :class:`~dominowave.chain.settings.ChainSettings` (``fidelity``, ``sleep``)."""
        return {"steps_per_collision": self.steps_per_collision, **numerics(self)}

    def params(self, **changes) -> ChainParams:
        """The :class:`~dominowave.chain.build.ChainParams` of this config."""
        fields = {name: getattr(self, name) for name in parameter_specs(ChainParams)}
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


ChainScenario = create_model(
    "ChainScenario",
    __base__=_ChainRun,
    __doc__=(
        "DEM chain of sphere clumps (dominowave.chain on dominowave.dem, paper section 3)."
        "\n\nThe physical fields are those of :class:`dominowave.chain.ChainParams`, derived"
        " from its declarations (names, defaults, units, ranges); the preset (``preset``,"
        " ``gap``, ``floor``) and the numerics (``fidelity``, ``sleep``) those of"
        " :class:`dominowave.chain.settings.ChainSettings`, derived the same way; plus how"
        " the run is driven: ``push_omega``, ``steps_per_collision`` and ``fit_from``."
    ),
    __module__=__name__,
    **fields_from_parameters(ChainParams),
    push_omega=(
        float | None,
        quantity(None, "rad/s", "push of domino 0 about its base (not set: sqrt(g/l))", gt=0),
    ),
    steps_per_collision=(
        int | None,
        quantity(
            None,
            "",
            "time steps per theory collision time T_c (sets dt; not set: 50, or for a"
            " softened contact the steps its tolerance allows, 10 at the default 2 %,"
            " chain.fidelity)",
            ge=10,
        ),
    ),
    **fields_from_parameters(ChainSettings),
    fit_from=(
        int | None,
        quantity(
            None,
            "",
            "also fit the front speed from domino K on (pitch-based, as cameras do);"
            " summary speed_fit_from",
            ge=1,
        ),
    ),
)

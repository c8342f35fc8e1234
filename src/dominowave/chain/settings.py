"""How a chain is set up and run besides its physics: a preset and the numerics.

:class:`~dominowave.chain.build.ChainParams` holds a chain's physical parameters. A
researcher gives two more things: a *preset* that takes those parameters from the
material data (``chain.presets.standard_domino``: the standard domino at a ``gap`` on a
``floor``), and the *numerics* of the run that do not change the physics but its cost and
accuracy (the contact's ``fidelity``, ``chain.fidelity``; ``sleep``, dominoes at rest put
to sleep, ``chain.scenario``). :class:`ChainSettings` declares them once
(:mod:`dominowave.params`), for the study files (``io.models.ChainScenario``) and the
command line (``dominowave chain``, ``cli.chain.RunOptions``), so that the two read the
same names, defaults, units and descriptions.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from dominowave.chain.fidelity import DEFAULT_TOLERANCE, Fidelity, check_fidelity
from dominowave.params import check_parameters, choice, parameter, parameter_specs, text

__all__ = ["ChainSettings", "Preset", "numerics"]

Preset = Literal["standard"]


@dataclass(frozen=True)
class ChainSettings:
    """A chain's preset and numerics (the module's docstring), checked when made.

    ``floor`` is checked by the material data it names, ``fidelity`` by
    ``chain.fidelity.check_fidelity`` (a tolerance in (0, 0.1] or ``"exact"``).
    """

    fidelity: Fidelity = text(
        "box chain given a Young's modulus (young, or a preset): exact (the material's"
        " contact) or the tolerance of the speed, the softest contact within it (not set:"
        f" {DEFAULT_TOLERANCE:g}; chain.fidelity)",
        group="numerics",
    )
    sleep: bool = parameter(
        True,
        "",
        "box chain: dominoes at rest are put to sleep (the speed changes by at most 4e-4, a"
        " long chain runs faster); false (--no-sleep) keeps every box awake (chain.scenario)",
        group="numerics",
    )
    preset: Preset | None = choice(
        Preset,
        "standard: the 48 x 24 x 7.5 mm box domino, every value from materials.toml"
        " (chain.presets.standard_domino; 3d unless a model is given; with a gap and a"
        " floor; not set: the chain of the other values)",
        default=None,
        group="preset",
    )
    gap: float | None = parameter(
        None, "m", "with a preset: clear gap d between neighbours", gt=0, group="preset"
    )
    floor: str | None = text(
        "with a preset: named floor (felt, glass, hardwood, laminate)", group="preset"
    )

    def __post_init__(self):
        check_parameters(self)
        check_fidelity(self.fidelity)


def numerics(settings) -> dict:
    """The numerics of ``settings`` (a :class:`ChainSettings`, or a study's chain that
    has its fields) as the keywords of ``chain.scenario.DominoChain``: each field of the
    ``numerics`` group by its name."""
    return {
        name: getattr(settings, name)
        for name, (_, spec) in parameter_specs(ChainSettings).items()
        if spec.group == "numerics"
    }

"""The one registry of scenario kinds: ``kind`` -> config model + run function.

The study loader (:mod:`dominowave.io.config`) reads a study's ``[scenario]`` against
the kind's model, the sweep engine (:mod:`dominowave.sweep.registry`) runs a point with
the kind's run function, and the study presets (Fig 6, compare-rods) are points of
kinds listed here too. Models and run functions are named ``"module:attribute"`` and
imported when first needed, so importing the registry imports no simulation code and
no module that registers a kind has to be imported first.

A run function has the signature ``run(config, ctx) -> RunResult``; a *steppable* kind
advances in steps that can be checkpointed and resumed
(:func:`dominowave.sweep.longrun.run_stepping`). Preset point kinds are not selectable
as the ``kind`` of a study file (``in_studies = False``): their studies are built by the
preset commands.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, replace
from typing import Any

__all__ = [
    "KINDS",
    "SCENARIO_MODELS",
    "ScenarioKind",
    "register_kind",
    "register_scenario_model",
    "set_runner",
]


def _load(target: str | Any) -> Any:
    """``target`` itself, or the attribute a ``"module:attribute"`` string names."""
    if not isinstance(target, str):
        return target
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)


@dataclass(frozen=True)
class ScenarioKind:
    """One scenario kind: its config model and run function (objects or ``"module:name"``)."""

    model: str | type
    runner: str | Callable | None
    steppable: bool = False
    in_studies: bool = True

    def load_model(self) -> type:
        return _load(self.model)

    def load_runner(self) -> Callable | None:
        return _load(self.runner)


KINDS: dict[str, ScenarioKind] = {
    "theory": ScenarioKind(
        "dominowave.io.models:TheoryScenario", "dominowave.sweep.run_theory:run_theory"
    ),
    "rods": ScenarioKind(
        "dominowave.io.models:RodsScenario", "dominowave.sweep.run_rods:run_rods", steppable=True
    ),
    "chain": ScenarioKind(
        "dominowave.io.models:ChainScenario",
        "dominowave.sweep.run_chain:run_chain",
        steppable=True,
    ),
    # the points of the study presets (dominowave paper-fig6, compare-rods, predict)
    "paper_fig6_member": ScenarioKind(
        "dominowave.sweep.fig6:Fig6Member",
        "dominowave.sweep.fig6:run_fig6_member",
        in_studies=False,
    ),
    "rods_comparison": ScenarioKind(
        "dominowave.sweep.compare_rods:RodsComparison",
        "dominowave.sweep.compare_rods:run_comparison",
        in_studies=False,
    ),
    "rods_omega_profile": ScenarioKind(
        "dominowave.sweep.compare_rods:OmegaProfilePoint",
        "dominowave.sweep.compare_rods:run_omega_profile",
        in_studies=False,
    ),
    "predict_sample": ScenarioKind(
        "dominowave.sweep.predict:PredictSample",
        "dominowave.sweep.predict:run_predict_sample",
        in_studies=False,
    ),
}
"""kind -> :class:`ScenarioKind`: every kind the package knows, in one place."""


def register_kind(
    model: type,
    runner: str | Callable | None = None,
    *,
    steppable: bool = False,
    in_studies: bool = True,
) -> type:
    """Make ``model`` (a :class:`~dominowave.io.schema.ScenarioModel` subclass) the kind
    ``model.kind`` run by ``runner``; returns ``model``."""
    kind = model.model_fields["kind"].default
    KINDS[kind] = ScenarioKind(model, runner, steppable, in_studies)
    return model


def register_scenario_model(model: type) -> type:
    """Class decorator: register ``model`` as a study kind (give its run function with
    :func:`set_runner`, or use :func:`register_kind`)."""
    return register_kind(model)


def set_runner(kind: str, runner: str | Callable, *, steppable: bool | None = None) -> None:
    """Give the registered ``kind`` the run function ``runner``."""
    if kind not in KINDS:
        raise ValueError(f"scenario.kind = {kind!r} is not registered (known: {_known()})")
    entry = KINDS[kind]
    KINDS[kind] = replace(
        entry, runner=runner, steppable=entry.steppable if steppable is None else steppable
    )


def _known() -> str:
    return ", ".join(sorted(KINDS))


class _StudyModels(Mapping):
    """Read-only view ``kind -> model`` of the kinds a study file may name."""

    def __getitem__(self, kind: str) -> type:
        entry = KINDS.get(kind)
        if entry is None or not entry.in_studies:
            raise KeyError(kind)
        return entry.load_model()

    def __iter__(self) -> Iterator[str]:
        return iter([k for k, e in KINDS.items() if e.in_studies])

    def __len__(self) -> int:
        return sum(e.in_studies for e in KINDS.values())


SCENARIO_MODELS: Mapping[str, type] = _StudyModels()
"""kind -> config model of the kinds a study file may name (a view of :data:`KINDS`)."""

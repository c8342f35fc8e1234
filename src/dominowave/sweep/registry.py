"""Scenario registry: ``kind`` -> run function, and the context a run gets.

A run function has the signature ``run(config, ctx) -> RunResult``: ``config``
is the validated pydantic model of its kind (:mod:`dominowave.io.models`),
``ctx`` a :class:`RunContext`. Run functions are looked up lazily by dotted
name, so importing the registry imports no simulation code.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

from dominowave.sweep.context import RunContext

__all__ = [
    "RUNNERS",
    "STEPPABLE",
    "RunContext",
    "get_runner",
    "is_steppable",
    "register_runner",
    "register_stepper",
]

RUNNERS: dict[str, str | Callable] = {
    "theory": "dominowave.sweep.run_theory:run_theory",
    "rods": "dominowave.sweep.run_rods:run_rods",
    "chain": "dominowave.sweep.run_chain:run_chain",
    # the points of the study presets (dominowave paper-fig6, compare-rods, predict)
    "paper_fig6_member": "dominowave.sweep.fig6:run_fig6_member",
    "rods_comparison": "dominowave.sweep.compare_rods:run_comparison",
    "rods_omega_profile": "dominowave.sweep.compare_rods:run_omega_profile",
    "predict_sample": "dominowave.sweep.predict:run_predict_sample",
}
"""kind -> run function or ``"module:function"``."""

STEPPABLE: set[str] = {"rods", "chain"}
"""Kinds whose runs advance in steps and can be checkpointed and resumed.

``rods`` and ``chain`` are registered here by name: each run function (above) is
``longrun.run_stepping`` with its stepper, what :func:`register_stepper` sets up,
without importing simulation code into the registry.
"""


def register_runner(kind: str, runner: str | Callable) -> None:
    """Make ``kind`` runnable by ``runner`` (a function or ``"module:function"``)."""
    RUNNERS[kind] = runner


def get_runner(kind: str) -> Callable:
    """The run function of ``kind`` (ValueError if the kind has none)."""
    try:
        runner = RUNNERS[kind]
    except KeyError:
        known = ", ".join(sorted(RUNNERS))
        raise ValueError(f"scenario.kind = {kind!r} has no run function (known: {known})") from None
    if isinstance(runner, str):
        module, _, name = runner.partition(":")
        runner = getattr(importlib.import_module(module), name)
    return runner


def register_stepper(kind: str, factory: Callable) -> None:
    """Make ``kind`` a checkpointable scenario: ``factory(config)`` returns its stepper.

    See :mod:`dominowave.sweep.longrun` for what a stepper provides.
    """
    import functools

    from dominowave.sweep.longrun import run_stepping

    RUNNERS[kind] = functools.partial(run_stepping, factory=factory)
    STEPPABLE.add(kind)


def is_steppable(kind: str) -> bool:
    """True if runs of ``kind`` can be checkpointed."""
    return kind in STEPPABLE

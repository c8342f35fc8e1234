"""What the sweep engine needs of a scenario kind: its run function, and the run context.

The kinds themselves -- config model, run function, steppable or not -- are listed
once, in :data:`dominowave.io.kinds.KINDS`; this module looks the run functions up there
(importing them on first use) and registers the run functions of kinds added later.
A run function has the signature ``run(config, ctx) -> RunResult``: ``config`` is the
validated pydantic model of its kind, ``ctx`` a :class:`RunContext`.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

from dominowave.io.kinds import KINDS, set_runner
from dominowave.sweep.context import RunContext

__all__ = [
    "RunContext",
    "get_runner",
    "is_steppable",
    "register_runner",
    "register_stepper",
    "steppable_kinds",
]


def register_runner(kind: str, runner: str | Callable) -> None:
    """Make the registered ``kind`` runnable by ``runner`` (a function or ``"module:function"``)."""
    set_runner(kind, runner)


def get_runner(kind: str) -> Callable:
    """The run function of ``kind`` (ValueError if the kind has none)."""
    entry = KINDS.get(kind)
    if entry is None or entry.runner is None:
        known = ", ".join(sorted(k for k, e in KINDS.items() if e.runner is not None))
        raise ValueError(f"scenario.kind = {kind!r} has no run function (known: {known})")
    return entry.load_runner()


def register_stepper(kind: str, factory: Callable) -> None:
    """Make the registered ``kind`` a checkpointable scenario: ``factory(config)`` returns
    its stepper.

    See :mod:`dominowave.sweep.longrun` for what a stepper provides.
    """
    from dominowave.sweep.longrun import run_stepping

    set_runner(kind, functools.partial(run_stepping, factory=factory), steppable=True)


def is_steppable(kind: str) -> bool:
    """True if runs of ``kind`` can be checkpointed."""
    entry = KINDS.get(kind)
    return entry is not None and entry.steppable


def steppable_kinds() -> list[str]:
    """The kinds whose runs can be checkpointed, sorted."""
    return sorted(k for k, e in KINDS.items() if e.steppable)

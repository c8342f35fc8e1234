"""The context a running scenario gets from the workflow (:class:`RunContext`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

__all__ = ["RunContext"]


@dataclass
class RunContext:
    """What the workflow offers a running scenario (all optional).

    progress : called as ``progress(sim_time=, end_time=, steps=, toppled=, dominoes=)``
        [s, s, -, -, -] whenever the scenario likes (it throttles itself); ``end_time``
        is the latest the run can end, ``dominoes`` the chain's length (0: unknown);
        None when quiet.
    vtk_every : VTK frames wanted every this many recorded frames (0: none); a scenario
        then also returns its spheres (``RunResult.spheres``) if it has any.
    checkpoint_dir : folder for checkpoints of long runs (None: no checkpoints).
    checkpoint_every_steps, checkpoint_every_seconds : how often to checkpoint.
    """

    progress: Callable[..., None] | None = None
    vtk_every: int = 0
    checkpoint_dir: Path | None = None
    checkpoint_every_steps: int = 0
    checkpoint_every_seconds: float = 0.0

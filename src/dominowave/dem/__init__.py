"""A general discrete-element engine: spheres, rigid clumps of spheres, rounded cuboids, capsules,
plane walls, linear and Hertz contacts with Cundall-Strack friction, YADE-style local
damping, blocked DOFs, and a numba-compiled time loop with recorders, compiled for each
kind of scene (:class:`SceneKind`).  Knows nothing about dominoes.

See docs/dem.md for the equations and the validation.
"""

from dominowave.dem.contact_rows import END, ONSET
from dominowave.dem.energy import ENERGY_NAMES
from dominowave.dem.engine import SceneKind
from dominowave.dem.scene import Scene
from dominowave.dem.simulation import (
    ContactEvents,
    ContactFrames,
    FrameRows,
    PairStats,
    RunResult,
    Simulation,
    StopCondition,
)
from dominowave.dem.state import Material, clump_mass_properties
from dominowave.dem.timestep import critical_timestep

__all__ = [
    "END",
    "ENERGY_NAMES",
    "ONSET",
    "ContactEvents",
    "ContactFrames",
    "FrameRows",
    "Material",
    "PairStats",
    "RunResult",
    "Scene",
    "SceneKind",
    "Simulation",
    "StopCondition",
    "clump_mass_properties",
    "critical_timestep",
]

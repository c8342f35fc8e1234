"""Box-chain runs reproduce stored arrays to the bit.

The per-step bookkeeping of the box contacts (the candidate list, the loop over the
moving boxes, held bodies, the integration) may be reorganised for speed; the
arithmetic of every contact and every body must stay the same.  Each scene below runs a
fixed number of steps and its final state (positions, orientations, velocities, the
contact rows with their shear histories, the energy ledger, the event log) is compared
bit for bit with ``data/box_identity.npz``, written by this module (``python
tests/dem/test_dem_box_identity.py --write``; stored_runs.py), in the floating-point
environment that wrote it (elsewhere to round-off: stored_runs.py).

Scenes: the 2D and the 3D (lateral asymmetry) chain of 10 boxes, held until touched,
with the event log and the energy ledger on; the 2D chain without held boxes; a 3D
chain of 6 boxes with the Hertz law (E, nu of a plastic) -- each covering the wave's
first collisions, onsets and ends of contacts and releases of held boxes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from stored_runs import (
    assert_as_stored,
    bodies_and_events,
    named,
    run_in_pieces,
    used_rows,
    write_main,
)

from dominowave.chain import ChainParams, DominoChain, Push
from dominowave.dem import Material, Scene

DATA = Path(__file__).parent / "data" / "box_identity.npz"

SCENES = {
    # name: (ChainParams fields, steps)
    "chain2d_held": (dict(n_dominoes=10, model="2d", held=True), 6000),
    "chain3d_held": (dict(n_dominoes=10, model="3d", lateral_asymmetry=0.01, held=True), 6000),
    "chain2d_free": (dict(n_dominoes=10, model="2d", held=False), 6000),
}
HERTZ_STEPS = 13000
HERTZ_ALPHA = 0.3588733627771574  # hertz_damping_ratio(0.6) where the arrays were written


def _chain(fields):
    p = ChainParams(shape="box", friction_dominoes=0.3, friction_floor=0.5, **fields)
    sim, _ = DominoChain(p, sleep=False).build(Push(omega=12.0), record=True, track_energy=True)
    return sim


def _hertz_chain():
    """Six standing 48 x 24 x 7.5 mm boxes of a plastic (E = 2.5 GPa, nu = 0.35), Hertz
    law, box 0 tipped towards box 1 (its front bottom edge at rest)."""
    scene = Scene(gravity=(0.0, 0.0, -9.81), normal_law="hertz")
    mat = scene.add_material(
        Material(density=1000.0, young=2.5e9, poisson=0.35, friction=0.4, restitution=0.6)
    )
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), mat)
    half = np.array([0.00375, 0.012, 0.024])
    r = 0.0005
    for n in range(6):
        centre = np.array([0.012 * n, 0.0, half[2]])
        w = v = np.zeros(3)
        if n == 0:
            w = np.array([0.0, 12.0, 0.0])
            v = np.cross(w, centre - np.array([half[0], 0.0, 0.0]))
        scene.add_box(centre, half, r, mat, velocity=v, angular_velocity=w, held=n > 0)
    sim = scene.build(dt=2e-6, track_energy=True, record_pairs=True, impact_speed=0.5)
    # the Tsuji ratio of e = 0.6 as on the machine that wrote the arrays: the ratio is the
    # root of an ODE solution (laws.hertz.hertz_damping_ratio), found to ~1e-12, and its last
    # digits follow the BLAS kernel NumPy picks for the processor
    assert sim.mats.hertz_damping[0, 0] == pytest.approx(HERTZ_ALPHA, rel=1e-10)
    sim.mats.hertz_damping[0, 0] = HERTZ_ALPHA
    return sim


ROW_FIELDS = ("i", "j", "key", "shear", "overlap", "fn")
"""The fields of the box contact rows compared."""


def _run(name):
    if name == "hertz3d":
        sim, steps = _hertz_chain(), HERTZ_STEPS
    else:
        fields, steps = SCENES[name]
        sim = _chain(fields)
    run_in_pieces(sim, steps)
    rows = used_rows(sim.boxes.rows, "rows", ROW_FIELDS)
    return named(name, {**bodies_and_events(sim), **rows})


NAMES = [*SCENES, "hertz3d"]


@pytest.mark.parametrize("name", NAMES)
def test_box_chain_bit_identical_to_reference(name):
    assert_as_stored(DATA, name, _run(name))


if __name__ == "__main__":
    write_main(DATA, NAMES, _run)

"""Sphere and clump runs reproduce stored arrays to the bit.

The sphere contacts (the Verlet list, the driver ``contact.compute_forces``, the law of
a contact point ``laws.point.point_law``) may be reorganised; the arithmetic of every
contact and every body must stay the same.  Each scene below runs a fixed number of
steps and its final state (positions, orientations, velocities, the contacts with their
shear histories, the energy ledger, the event log) is compared bit for bit with
``data/clump_identity.npz``, computed by this module (``python
tests/dem/test_dem_clump_identity.py --write``; stored_runs.py), in the floating-point
environment that wrote it (elsewhere to round-off: stored_runs.py).

Scenes: through the general kernels, the 3D clump chain of 6 dominoes (lateral
asymmetry, held until touched) with the contact-point shear kinematics and with YADE's,
and 27 spheres of two materials dropped, spinning, into a box of five walls
(sphere-sphere and sphere-wall contacts that slide, roll and end); through the planar
kernels (contact.compute_forces_planar), the 2D clump chain of 6 dominoes with either
shear kinematics.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from dem_scenes import spheres_in_a_box
from stored_runs import (
    assert_as_stored,
    bodies_and_events,
    named,
    run_in_pieces,
    used_rows,
    write_main,
)

from dominowave.chain import ChainParams, DominoChain, Push

DATA = Path(__file__).parent / "data" / "clump_identity.npz"

CHAINS = {
    # name: (ChainParams fields, steps)
    "clump3d": (dict(model="3d", lateral_asymmetry=0.01), 12000),
    "clump3d_yade": (dict(model="3d", lateral_asymmetry=0.01, shear_kinematics="yade"), 12000),
    "clump2d": (dict(model="2d"), 12000),
    "clump2d_yade": (dict(model="2d", shear_kinematics="yade"), 12000),
}
BOX_STEPS = 6000


def _chain(fields):
    p = ChainParams(
        shape="clump", n_dominoes=6, held=True, friction_dominoes=0.3, friction_floor=0.5,
        restitution=0.5, **fields,
    )  # fmt: skip
    sim, _ = DominoChain(p).build(Push(omega=12.0), record=True, track_energy=True)
    return sim


CONTACT_FIELDS = ("i", "j", "shear", "overlap", "vn", "fn", "fn_viscous")
"""The fields of the sphere contacts compared (a row touches while its overlap is positive)."""


def _run(name):
    if name == "spheres":
        sim, steps = spheres_in_a_box(), BOX_STEPS
    else:
        fields, steps = CHAINS[name]
        sim = _chain(fields)
    sim.planar_kernels = name.startswith("clump2d")  # (else the general kernels)
    assert sim.planar == sim.planar_kernels  # (the 2D chains are planar, the others not)
    run_in_pieces(sim, steps)
    contacts = used_rows(sim.contacts, "contacts", CONTACT_FIELDS)
    return named(name, {**bodies_and_events(sim), **contacts})


NAMES = [*CHAINS, "spheres"]


@pytest.mark.parametrize("name", NAMES)
def test_sphere_contacts_bit_identical_to_reference(name):
    got = _run(name)
    assert float(np.abs(got[f"{name}/contacts_shear"]).max()) > 0.0  # (shear springs)
    assert_as_stored(DATA, name, got)


if __name__ == "__main__":
    write_main(DATA, NAMES, _run)

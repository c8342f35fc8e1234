"""Runs compared with stored arrays to the bit: the identity tests of the engine.

A scene runs a fixed number of steps, in two pieces (each return to Python and re-entry
must not change the result either), and its final state -- the bodies, the contacts with
their shear histories, the energy ledger, the event log -- is compared with arrays that a
module wrote with its ``--write`` option (:func:`write_main`).  Regenerate them only for a
change that is meant to alter the arithmetic, and say so in the commit.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

BODY_ARRAYS = ("pos", "quat", "vel", "omega", "angmom", "held")
"""Arrays of ``sim.bodies`` compared."""


def run_in_pieces(sim, steps: int) -> None:
    """Advance ``sim`` by ``steps`` steps in two calls."""
    sim.run(n_steps=steps // 3)
    sim.run(n_steps=steps - steps // 3)


def bodies_and_events(sim) -> dict[str, np.ndarray]:
    """The bodies' arrays (:data:`BODY_ARRAYS`), the energies of the last step (stored
    in the springs, dissipated: dem.energy.ENERGY_NAMES), the energy ledger and the event
    log."""
    rec = sim.rec
    e = int(rec.ev_n[0])
    out = {name: getattr(sim.bodies, name) for name in BODY_ARRAYS}
    out["energy"] = rec.energy_now
    out["ledger"] = rec.ledger
    out.update({k: getattr(rec, k)[:e] for k in ("ev_time", "ev_i", "ev_j", "ev_kind")})
    return out


def used_rows(table, prefix: str, fields) -> dict[str, np.ndarray]:
    """The used part (``table.n[0]`` rows) of the ``fields`` of a contact table (the
    spheres' ``sim.contacts``, the boxes' ``sim.boxes.rows``), keyed ``prefix_field``."""
    n = int(table.n[0])
    return {f"{prefix}_{k}": getattr(table, k)[:n] for k in fields}


def named(name: str, arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """``arrays`` copied, their keys prefixed with the scene's ``name``."""
    return {f"{name}/{k}": np.array(v, copy=True) for k, v in arrays.items()}


def assert_as_stored(path: Path, name: str, got: dict[str, np.ndarray]) -> None:
    """The arrays of scene ``name`` in ``got`` are the stored ones, every one, equal
    to the bit; the scene has contact events."""
    ref = np.load(path)
    assert sorted(got) == sorted(k for k in ref.files if k.startswith(f"{name}/"))
    assert int(got[f"{name}/ev_time"].size) > 0
    for key, value in got.items():
        np.testing.assert_array_equal(value, ref[key], err_msg=key, strict=True)


def write_main(path: Path, names, run) -> None:
    """The ``--write`` entry of an identity test module: ``run(name)`` of every scene
    into ``path``."""
    if sys.argv[1:] != ["--write"]:
        raise SystemExit(f"usage: python {sys.argv[0]} --write")
    arrays = {}
    for name in names:
        arrays.update(run(name))
    path.parent.mkdir(exist_ok=True)
    np.savez_compressed(path, **arrays)
    print(f"wrote {path}: {len(arrays)} arrays")

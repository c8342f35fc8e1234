"""Runs compared with stored arrays to the bit: the identity tests of the engine.

A scene runs a fixed number of steps, in two pieces (each return to Python and re-entry
must not change the result either), and its final state -- the bodies, the contacts with
their shear histories, the energy ledger, the event log -- is compared with arrays that a
module wrote with its ``--write`` option (:func:`write_main`).  Regenerate them only for a
change that is meant to alter the arithmetic, and say so in the commit.

The last bit of a run depends on more than the code: on the CPU, which chooses the code
paths of the C library's and numpy's functions and the instructions numba compiles to,
and on the versions of numba, llvmlite, numpy and the C library.  The same clump and
sphere runs differ by up to 5e-8 of an array's scale between two AMD EPYC generations,
their integer arrays (events, contact pairs) not at all.  So the stored arrays carry the
floating-point environment that wrote them (:func:`float_environment`): in that
environment they are compared to the bit; in another, integers exactly and floats to
:data:`ROUNDOFF` of each array's largest magnitude, with a warning that names both
environments.  To compare bits on a new machine before a change, write the arrays there
with the code before it.
"""

from __future__ import annotations

import platform
import sys
import warnings
from pathlib import Path

import llvmlite
import llvmlite.binding
import numba
import numpy as np

ROUNDOFF = 1e-6
"""Largest difference of a float array from the stored one, relative to the array's largest
magnitude, in a floating-point environment other than the writer's: 20 times the largest
seen between two CPUs (5e-8, the contact forces of a clump chain after 12000 steps)."""

ENVIRONMENT_KEY = "environment"
"""Key of the writer's :func:`float_environment` in a file of stored arrays."""

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


def float_environment() -> str:
    """What besides the code decides the last bit of a run: the CPU numba compiles for,
    the machine, the C library and the versions of numba, llvmlite and numpy."""
    libc = " ".join(platform.libc_ver())
    return (
        f"cpu {llvmlite.binding.get_host_cpu_name()}, {platform.machine()}, libc {libc}, "
        f"numba {numba.__version__}, llvmlite {llvmlite.__version__}, numpy {np.__version__}"
    )


def assert_as_stored(path: Path, name: str, got: dict[str, np.ndarray]) -> None:
    """The arrays of scene ``name`` in ``got`` are the stored ones, every one: equal to the
    bit in the environment that wrote them, else to round-off (module docstring); the
    scene has contact events."""
    ref = np.load(path)
    assert sorted(got) == sorted(k for k in ref.files if k.startswith(f"{name}/"))
    assert int(got[f"{name}/ev_time"].size) > 0
    writer = str(ref[ENVIRONMENT_KEY])
    here = float_environment()
    foreign = writer != here
    if foreign:
        warnings.warn(
            f"{path.name} was written in another floating-point environment ({writer}; "
            f"here: {here}): {name} compared to {ROUNDOFF:g} of each array's scale, not to "
            "the bit",
            stacklevel=2,
        )
    for key, value in got.items():
        if not foreign or value.dtype.kind != "f":
            np.testing.assert_array_equal(value, ref[key], err_msg=key, strict=True)
        else:
            scale = float(np.abs(ref[key]).max(initial=0.0))
            np.testing.assert_allclose(
                value, ref[key], rtol=0.0, atol=ROUNDOFF * scale, err_msg=key, strict=True
            )


def write_main(path: Path, names, run) -> None:
    """The ``--write`` entry of an identity test module: ``run(name)`` of every scene
    into ``path``."""
    if sys.argv[1:] != ["--write"]:
        raise SystemExit(f"usage: python {sys.argv[0]} --write")
    arrays = {ENVIRONMENT_KEY: np.array(float_environment())}
    for name in names:
        arrays.update(run(name))
    path.parent.mkdir(exist_ok=True)
    np.savez_compressed(path, **arrays)
    print(f"wrote {path}: {len(arrays)} arrays")

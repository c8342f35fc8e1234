"""Chains of real dominoes built from the shipped material data (``chain/data/materials.toml``).

``standard_domino(gap=..., floor=...)`` is the common 48 x 24 x 7.5 mm toppling domino as a
3D DEM chain, every value from :func:`dominowave.chain.materials.load_materials`:

===================  ==========================================  =====================
ChainParams field    material entry                              how
===================  ==========================================  =====================
height, width,       ``domino.height``, ``.width``, ``.thickness``  as given
thickness
d_over_l             (the ``gap`` argument) / ``domino.height``  d is the clear gap
density              ``domino.mass``                             bead density giving
                                                                 the domino that mass
young                ``plastic.youngs_modulus``                  ``young_rule="paper"``
friction_dominoes    ``friction.domino_domino``                  as given
friction_floor       ``friction.floor.<floor>``                  as given
restitution          ``restitution.domino_domino``               as given
===================  ==========================================  =====================

Not used by this model (listed in :data:`UNUSED`): ``plastic.density`` (the clump's
mass is the domino's), ``plastic.poisson_ratio`` (linear contacts) and
``restitution.domino_floor`` (one restitution for every contact of the clump model).
The domino is the paper's clump of spheres (``dominowave.chain.build``) until the
shape-true box chain exists.

Nothing is fitted to wave-speed data: the values are the data file's nominal values, or
the ``values`` a caller gives (e.g. samples of the ranges, ``dominowave.sweep.predict``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from dominowave.chain.build import ChainParams
from dominowave.chain.materials import Entry, Materials, load_materials
from dominowave.checks import check_in_range

__all__ = ["SAMPLED", "UNUSED", "standard_domino", "standard_entries"]

SAMPLED = ("mass", "young", "friction_dominoes", "friction_floor", "restitution")
"""The material values a standard-domino chain takes from the data, by their names here."""

UNUSED = ("plastic.density", "plastic.poisson_ratio", "restitution.domino_floor")
"""Material entries the clump model has no use for (see the module docstring)."""


def standard_entries(floor: str, materials: Materials | None = None) -> dict[str, Entry]:
    """The material entry behind each name of :data:`SAMPLED` for the floor ``floor``."""
    mat = materials or load_materials()
    return {
        "mass": mat.domino.mass,
        "young": mat.plastic.youngs_modulus,
        "friction_dominoes": mat.friction_domino_domino,
        "friction_floor": mat.floor_friction(floor),
        "restitution": mat.restitution_domino_domino,
    }


def standard_domino(
    *,
    gap: float,
    floor: str,
    n_dominoes: int = 30,
    materials: Materials | None = None,
    values: Mapping[str, float] | None = None,
    **overrides,
) -> ChainParams:
    """``ChainParams`` of a chain of standard 48 x 24 x 7.5 mm dominoes (3D model).

    ``gap`` [m] is the clear distance ``d`` between neighbours (pitch ``d + s``), inside
    ``(0, l)``; ``floor`` a named floor of the data (``hardwood``, ``felt``, ...);
    ``materials`` another materials file (default: the shipped one). ``values`` replaces
    nominal material values by name (:data:`SAMPLED`: ``mass`` [kg], ``young`` [Pa],
    ``friction_dominoes``, ``friction_floor``, ``restitution`` [1]); each must lie in its
    entry's range. ``overrides`` are ChainParams fields set last (e.g. ``model="2d"``,
    ``stiffness_ratio=1e4`` for a cheap test chain; a stiffness given this way replaces
    the modulus).
    """
    mat = materials or load_materials()
    entries = standard_entries(floor, mat)
    chosen = {name: entry.value for name, entry in entries.items()}
    for name, value in (values or {}).items():
        if name not in entries:
            raise ValueError(f"values: {name!r} is not one of {', '.join(SAMPLED)}")
        lo, hi = entries[name].range
        check_in_range(name, value, lo, hi, lo_inclusive=True, hi_inclusive=True)
        chosen[name] = float(value)
    height = mat.domino.height.value
    check_in_range("gap", gap, 0.0, height)
    params = ChainParams(
        n_dominoes=n_dominoes,
        height=height,
        thickness=mat.domino.thickness.value,
        width=mat.domino.width.value,
        d_over_l=gap / height,
        model="3d",
        young=chosen["young"],
        young_rule="paper",
        friction_dominoes=chosen["friction_dominoes"],
        friction_floor=chosen["friction_floor"],
        restitution=chosen["restitution"],
    )
    # the bead density that gives the domino its mass (ChainParams.mass is linear in it)
    params = params.with_(density=params.density * chosen["mass"] / params.mass)
    if not math.isclose(params.mass, chosen["mass"], rel_tol=1e-12):
        raise AssertionError("bead density does not reproduce the domino mass")
    return params.with_(**overrides) if overrides else params

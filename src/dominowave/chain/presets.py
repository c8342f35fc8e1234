"""Chains of real dominoes built from the shipped material data (``chain/data/materials.toml``).

``standard_domino(gap=..., floor=...)`` is the common 48 x 24 x 7.5 mm toppling domino as a
3D chain of box dominoes (``shape = "box"``: one rounded cuboid each,
``dominowave.chain.build``), every value from
:func:`dominowave.chain.materials.load_materials`:

======================  ===========================================  ==================
ChainParams field       material entry                               how
======================  ===========================================  ==================
height, width,          ``domino.height``, ``.width``, ``.thickness``  as given
thickness
d_over_l                (the ``gap`` argument) / ``domino.height``   d is the clear gap
density                 ``domino.mass``                              ``m / (l w s)``
young                   ``plastic.youngs_modulus``                   ``young_rule="paper"``
friction_dominoes       ``friction.domino_domino``                   as given
friction_floor          ``friction.floor.<floor>``                   as given
restitution_dominoes    ``restitution.domino_domino``                as given
restitution_floor       ``restitution.domino_floor``                 as given
======================  ===========================================  ==================

Not used (listed in :data:`UNUSED`): ``plastic.density`` -- the domino's weighed mass
(8 g) sets the dynamics; the plastic's density over the full box would give 9.16 g, the
upper end of the mass range, which the sampling of ``domino.mass`` covers -- and
``plastic.poisson_ratio`` (linear contacts). The edges are rounded with the box default
``r = s/20``, which is also the radius of the modulus's contact spring (``pi r E / 2``).

Nothing is fitted to wave-speed data: the values are the data file's nominal values, or
the ``values`` a caller gives (e.g. samples of the ranges, ``dominowave.sweep.predict``).
"""

from __future__ import annotations

from collections.abc import Mapping

from dominowave.chain.build import ChainParams
from dominowave.chain.materials import Entry, Materials, load_materials
from dominowave.checks import check_in_range

__all__ = ["SAMPLED", "UNUSED", "standard_domino", "standard_entries"]

SAMPLED = (
    "mass",
    "young",
    "friction_dominoes",
    "friction_floor",
    "restitution_dominoes",
    "restitution_floor",
)
"""The material values a standard-domino chain takes from the data, by their names here."""

UNUSED = ("plastic.density", "plastic.poisson_ratio")
"""Material entries the preset does not use (see the module docstring)."""


def standard_entries(floor: str, materials: Materials | None = None) -> dict[str, Entry]:
    """The material entry behind each name of :data:`SAMPLED` for the floor ``floor``."""
    mat = materials or load_materials()
    return {
        "mass": mat.domino.mass,
        "young": mat.plastic.youngs_modulus,
        "friction_dominoes": mat.friction_domino_domino,
        "friction_floor": mat.floor_friction(floor),
        "restitution_dominoes": mat.restitution_domino_domino,
        "restitution_floor": mat.restitution_domino_floor,
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
    """``ChainParams`` of a chain of standard 48 x 24 x 7.5 mm box dominoes (3D model).

    ``gap`` [m] is the clear distance ``d`` between neighbours (pitch ``d + s``), inside
    ``(0, l)``; ``floor`` a named floor of the data (``hardwood``, ``felt``, ...);
    ``materials`` another materials file (default: the shipped one). ``values`` replaces
    nominal material values by name (:data:`SAMPLED`: ``mass`` [kg], ``young`` [Pa],
    ``friction_dominoes``, ``friction_floor``, ``restitution_dominoes``,
    ``restitution_floor`` [1]); each must lie in its entry's range. ``overrides`` are
    ChainParams fields set last (e.g. ``model="2d"``, ``stiffness_ratio=1e4`` for a cheap
    test chain: a stiffness given this way replaces the modulus).
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
    thickness, width = mat.domino.thickness.value, mat.domino.width.value
    params = ChainParams(
        n_dominoes=n_dominoes,
        shape="box",
        height=height,
        thickness=thickness,
        width=width,
        d_over_l=gap / height,
        model="3d",
        density=chosen["mass"] / (height * width * thickness),
        young=chosen["young"],
        young_rule="paper",
        friction_dominoes=chosen["friction_dominoes"],
        friction_floor=chosen["friction_floor"],
        restitution_dominoes=chosen["restitution_dominoes"],
        restitution_floor=chosen["restitution_floor"],
    )
    return params.with_(**overrides) if overrides else params

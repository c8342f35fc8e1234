"""Domino chain geometry and materials from physical parameters (paper section 3, Fig 6A).

A domino has one of two shapes (``ChainParams.shape``): ``"clump"``, the paper's rigid
clump of equal spheres (below), or ``"box"``, one rigid rounded cuboid (end of this
docstring). A clump domino is a clump of equal spheres of diameter ``s`` (its thickness):

* **2D model** -- one column of spheres in the xz plane; the DEM blocks ``y``,
  ``rx`` and ``rz`` so the domino only moves in that plane (the paper's default,
  ``s/l = 0.1`` gives 10 spheres per domino);
* **3D model** -- ``n_across`` such columns side by side across the width ``w``,
  free in all six degrees of freedom; an optional seeded yaw of each domino (the
  *lateral asymmetry*) makes the hit land on one side first and triggers the
  lateral rotation the paper describes.

Conventions (all SI):

* ``d`` is the clear gap between neighbouring dominoes, so the pitch (distance
  between the columns' axes) is ``d + s``; ``d/l`` sets the theory's
  ``beta = asin(d/l)`` and eq 34 uses ``d + s``.
* The column's spheres are equally spaced from ``z = R`` to ``z = l - R``
  (``R = s/2``): the domino is exactly ``l`` tall. With the default
  ``spheres_per_column = round(l/s)`` neighbouring spheres touch; more spheres
  overlap (resolution study), and the bead density is scaled so that the domino
  mass stays that of the touching column: ``m = round(l/s) * rho * 4/3 pi R^3``
  per column (overlaps are not subtracted, as in YADE's clumps).
* Standing rule: a single-sphere base is an inverted pendulum that round-off
  topples within seconds. ``held=True`` keeps an untouched domino fixed until a
  moving body first touches it (the engine's *held* flag); ``base="two"``
  replaces the bottom sphere by two spheres of radius ``R/2`` side by side at
  ``x = +-R/2`` (four times the bead density, so the same mass), a base that is
  statically stable for tilts below ``atan((R/2) / h_cm)``.
* Friction: spheres of the bottom layer carry the floor friction ``phi_f``, the
  others ``phi_d``; the engine takes ``min`` per contact (paper section 3), so
  domino-domino contacts have ``phi_d`` unless two bases touch.
* Stiffness: every contact (sphere-sphere and sphere-floor) has the same normal
  spring ``k_n``, given directly (``kn`` [N/m]), as the paper's ratio ``k/k*`` with
  ``k* = m g / l`` (Fig 4, 6C) where ``k`` is the paper's per-particle stiffness
  (eq 23) so that ``k_n = k/2`` (eq 24; ``theory.contact_stiffness``), or from a
  Young's modulus with a named convention: ``"paper"`` ``k_n = pi R E / 2``
  (eq 24) or ``"yade"`` ``k_n = E R`` (YADE's FrictPhys for two equal spheres).
  In 3D, ``k*`` uses the mass of ONE column, so a 3D domino of the same material
  has the same ``k_n`` per contact as the 2D one (and, with ``n_across`` columns
  touching in parallel, the same collision time): 2D and 3D are comparable.
* The floor is the plane ``z = 0``; dominoes start at the static overlap
  ``m g / (n_base k_n)`` so that a released domino is already in equilibrium.

A **box** domino (``shape = "box"``) is one rigid rounded cuboid (``dem.Scene.add_box``)
of thickness ``s``, width ``w`` and height ``l`` whose edges are rounded with radius
``r = rounding`` (default ``s/20``, ``0 < r < s/2``), with the uniform cuboid's mass
``m = rho l w s`` and inertia, in 2D (planar: ``y``, ``rx``, ``rz`` blocked) and 3D alike.
It stands on its own flat base in equilibrium, so holding it until touched changes
nothing but the cost (docs/shape.md, "Holding a box until it is touched"); the clump's
``spheres_per_column`` and ``base`` do not apply to it (and the box's ``rounding``,
``restitution_dominoes``, ``restitution_floor`` not to a clump).

* Stiffness: the box keeps the clump's *pair* stiffness per unit domino weight, so that
  a box and a clump chain of the same ``k/k*`` have the same collision time (eq 31).
  The paper's ``k`` is per particle and two particles touch in series, ``k_n = k / 2``
  (eqs 22-24); a clump domino carries that spring on one sphere contact per column
  (``k* = m_column g / l``). A box domino meets the next one (and the floor) along an
  edge whose two ends are the contact points of the rounded cuboid (a planar scene
  counts its one point twice), so each point gets half of it: ``k_n = k / 4`` with
  ``k* = m g / l`` of the whole box; the pair stiffness is ``2 k_n = k / 2``, as a 2D
  clump's. ``kn`` is the spring of one contact point; ``young`` gives ``k_n`` by the
  rule of ``young_rule`` with the rounding ``r`` as the radius (eq 24: ``pi r E / 2``).
* Restitution: ``restitution`` is that of every contact (the clump's one value);
  ``restitution_dominoes`` and ``restitution_floor`` set the box's domino-domino and
  domino-floor contacts apart (not set: ``restitution``).
* The box starts at the static overlap ``m g / (4 k_n)`` (four corner points on the floor).

**Hertz contacts** (``normal_law = "hertz"``, box only, with ``young`` and ``poisson``): every
contact point of a box pushes with Hertz's ``F = K delta^{3/2}``, ``K = 4/3 E* sqrt(r)``,
``1/E* = 2 (1 - nu^2) / E`` (two bodies of the same material; the floor is given the
dominoes' material), the rounding ``r`` as the radius of curvature (``dem.laws.hertz``), and the
Tsuji dashpot of the pair's restitution.  The tangential spring stays the linear rule's
(``kt_ratio`` times ``pi r E / 2``, eq 24 with ``R = r``): ``contact_stiffness`` is that spring,
and the theory's estimates (time step, travel time) use it.  A box stands at its Hertz sink:
``m g / 4 = K delta^{3/2}`` on its four corner points (a planar box: two, each counted twice).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from dominowave.checks import check_in_range
from dominowave.params import check_parameters, choice, parameter
from dominowave.theory import contact_stiffness, contact_stiffness_from_material
from dominowave.units import G_STANDARD, k_star

__all__ = [
    "ChainParams",
    "DominoBox",
    "DominoShape",
    "Placement",
    "chain_positions",
    "domino_box",
    "domino_shape",
    "place_domino",
    "placement",
    "yaw_matrix",
]

Model = Literal["2d", "3d"]
Shape = Literal["clump", "box"]
Base = Literal["one", "two"]
YoungRule = Literal["paper", "yade"]
NormalLaw = Literal["linear", "hertz"]

CLUMP_ONLY = ("spheres_per_column", "base")
"""Options of ``shape = "clump"`` that a box refuses."""
BOX_ONLY = ("rounding", "restitution_dominoes", "restitution_floor")
"""Options of ``shape = "box"`` that a clump refuses."""
ShearKinematics = Literal["contact_point", "yade"]


def _restitution(doc: str):
    """The declaration of a normal restitution coefficient in (0, 1] (the normal law's
    dashpot, :mod:`dominowave.dem.laws`), not set by default, described by ``doc``."""
    return parameter(None, "", doc, gt=0, le=1, group="contact")


@dataclass(frozen=True)
class ChainParams:
    """Physical parameters of a domino chain (SI units).

    Give the contact stiffness in exactly one way: ``stiffness_ratio`` (the paper's
    k/k*, default 1e4 when nothing else is given; ``k_n = k/2``), ``kn`` [N/m] (the
    contact spring), or ``young`` [Pa] with ``young_rule``. ``kt_ratio`` is the
    tangential/normal stiffness ratio; ``shear_kinematics`` what drives the tangential
    spring (``dem.Scene``): ``"contact_point"``, the relative velocity of the material
    points at the contact, or ``"yade"``, YADE's ratcheting-free rate (for comparisons with
    YADE).
    ``damping`` is the engine's local (non-viscous, YADE-style) damping
    coefficient in [0, 1); ``restitution`` (None = elastic) adds a normal dashpot.
    ``shape`` picks the domino: ``"clump"`` (the paper's, default) or ``"box"`` (one rounded
    cuboid, ``rounding``); each refuses the other's options (module docstring). For a box
    ``k/k*``, ``kn`` and ``young`` mean per contact point (``k_n = k/4``, module docstring),
    and ``restitution_dominoes`` / ``restitution_floor`` set the two contact pairs apart.
    """

    n_dominoes: int = parameter(30, "", "number of dominoes", ge=2, le=100_000, group="layout")
    shape: Shape = choice(
        Shape,
        "domino shape: clump (a clump of spheres, the paper's) or box (one rounded cuboid)",
        group="shape",
    )
    height: float = parameter(0.05, "m", "domino height l", gt=0, group="shape")
    thickness: float = parameter(
        0.005,
        "m",
        "domino thickness s = sphere diameter (below l/2)",
        gt=0,
        group="shape",
    )
    width: float = parameter(
        0.025, "m", "domino width (clump: the 3D model; box: always)", gt=0, group="shape"
    )
    d_over_l: float = parameter(
        0.4, "", "spacing ratio d/l (d = clear gap)", gt=0, lt=1, group="layout"
    )
    density: float = parameter(
        1000.0,
        "kg/m^3",
        "density (clump: of the beads; box: of the cuboid)",
        gt=0,
        group="shape",
    )
    rounding: float | None = parameter(
        None,
        "m",
        "box only: radius r of the rounded edges, 0 < r < s/2 (not set: s/20)",
        gt=0,
        group="shape",
    )
    stiffness_ratio: float | None = parameter(
        None,
        "",
        "paper's k/k* (k per particle, contact spring k_n = k/2, eq 24; a box's k/4 per"
        " contact point); 1e4 when neither kn nor young is given",
        gt=0,
        group="contact",
    )
    kn: float | None = parameter(
        None, "N/m", "contact spring k_n per contact point, directly", gt=0, group="contact"
    )
    young: float | None = parameter(
        None, "Pa", "Young's modulus (with young_rule)", gt=0, group="contact"
    )
    normal_law: NormalLaw = choice(
        NormalLaw,
        "normal force of a contact point: linear (k_n delta) or hertz (box with young: 4/3 E*"
        " sqrt(r) delta^{3/2})",
        group="contact",
    )
    poisson: float | None = parameter(
        None,
        "",
        "hertz only: Poisson's ratio nu in [0, 0.5) (not set: 0.3)",
        ge=0,
        lt=0.5,
        group="contact",
    )
    young_rule: YoungRule = choice(
        YoungRule, "k_n from young: paper pi R E / 2 (eq 24) or yade E R", group="contact"
    )
    kt_ratio: float = parameter(
        1.0,
        "",
        "tangential / normal contact stiffness",
        gt=0,
        allow_inf=True,
        group="contact",
    )
    shear_kinematics: ShearKinematics = choice(
        ShearKinematics,
        "tangential spring rate: contact_point (material points, the default) or yade",
        group="contact",
    )
    friction_dominoes: float = parameter(
        0.0, "", "friction between dominoes phi_d", ge=0, group="contact"
    )
    friction_floor: float = parameter(
        0.3, "", "friction with the floor phi_f", ge=0, group="contact"
    )
    damping: float = parameter(0.0, "", "local (YADE-style) damping", ge=0, lt=1, group="contact")
    restitution: float | None = _restitution(
        "normal restitution of every contact (not set = elastic)"
    )
    restitution_dominoes: float | None = _restitution(
        "box only: restitution between dominoes (not set: restitution)"
    )
    restitution_floor: float | None = _restitution(
        "box only: restitution with the floor (not set: restitution)"
    )
    model: Model = choice(Model, "2d: xz plane only; 3d: free", group="layout")
    spheres_per_column: int | None = parameter(
        None,
        "",
        "clump only: spheres per column (not set: round(l/s), touching)",
        ge=2,
        group="shape",
    )
    base: Base | None = choice(
        Base,
        "clump only: one bottom sphere, or two half-size (not set: one)",
        default=None,
        group="shape",
    )
    held: bool = parameter(
        True, "", "untouched dominoes are held until first touched", group="layout"
    )
    lateral_asymmetry: float = parameter(
        0.0,
        "rad",
        "placement error: yaw of each domino, uniform in +-amplitude (3d)",
        ge=0,
        lt=0.1,
        group="placement",
    )
    placement_along: float = parameter(
        0.0,
        "m",
        "placement error: shift along the line, uniform in +-amplitude",
        ge=0,
        group="placement",
    )
    placement_across: float = parameter(
        0.0,
        "m",
        "placement error: shift across the line, uniform in +-amplitude (3d)",
        ge=0,
        group="placement",
    )
    push_error: float = parameter(
        0.0,
        "",
        "placement error of the push: relative, push x (1 + push_error N(0, 1))",
        ge=0,
        group="placement",
    )
    asymmetry_seed: int = parameter(
        0,
        "",
        "seed of the placement errors (yaw, along, across, push)",
        ge=0,
        group="placement",
    )
    g: float = parameter(G_STANDARD, "m/s^2", "gravitational acceleration", gt=0, group="layout")

    def __post_init__(self):
        check_parameters(self)
        # the rules that join several fields
        check_in_range("thickness", self.thickness, 0.0, self.height / 2)
        self._check_shape_options()
        if self.rounding is not None:
            check_in_range("rounding", self.rounding, 0.0, self.thickness / 2)
        # neighbours must not overlap however the errors fall: each may move by the amplitude
        check_in_range(
            "placement_along", self.placement_along, 0.0, self.spacing / 2, lo_inclusive=True
        )
        if self.placement_across > 0 and self.model != "3d":
            raise ValueError(
                f"placement_across = {self.placement_across!r} m needs model = '3d'"
                f" (got model = {self.model!r}: a 2D chain has no across direction)"
            )
        given = [x for x in (self.stiffness_ratio, self.kn, self.young) if x is not None]
        if len(given) > 1:
            raise ValueError(
                "give the stiffness once: stiffness_ratio, kn or young "
                f"(got stiffness_ratio={self.stiffness_ratio}, kn={self.kn}, young={self.young})"
            )
        self._check_normal_law()

    def _check_normal_law(self) -> None:
        """Hertz needs a box and a Young's modulus; ``poisson`` is Hertz's alone."""
        if self.normal_law == "linear":
            if self.poisson is not None:
                raise ValueError(
                    f"poisson = {self.poisson!r} is an option of normal_law = 'hertz' only;"
                    " with normal_law = 'linear' leave it unset (None)"
                )
            return
        if self.shape != "box":
            raise ValueError(
                f"normal_law = 'hertz' needs shape = 'box' (got shape = {self.shape!r}: a"
                " clump's sphere contacts are linear)"
            )
        for name in ("stiffness_ratio", "kn"):
            value = getattr(self, name)
            if value is not None:
                raise ValueError(
                    f"{name} = {value!r} is a stiffness of normal_law = 'linear'; with"
                    " normal_law = 'hertz' give young [Pa] (and poisson) instead"
                )
        if self.young is None or not math.isfinite(self.young):
            raise ValueError(
                f"normal_law = 'hertz' needs young, Young's modulus in (0, inf) Pa (got"
                f" young = {self.young!r})"
            )
        if self.young_rule != "paper":
            raise ValueError(
                f"young_rule = {self.young_rule!r}: with normal_law = 'hertz' the tangential"
                " spring takes the paper rule pi r E / 2; leave young_rule = 'paper'"
            )

    def _check_shape_options(self) -> None:
        """Refuse an option of the other shape: one error naming it, its value, the shape."""
        if self.shape == "box":
            other, options = "clump", CLUMP_ONLY
        else:
            other, options = "box", BOX_ONLY
        for name in options:
            value = getattr(self, name)
            if value is not None:
                raise ValueError(
                    f"{name} = {value!r} is an option of shape = {other!r} only; with shape ="
                    f" {self.shape!r} leave it unset (None)"
                )

    # --- derived geometry -------------------------------------------------------------
    @property
    def radius(self) -> float:
        """Sphere radius ``R = s/2`` [m] (the clump's beads)."""
        return self.thickness / 2.0

    @property
    def rounding_radius(self) -> float:
        """Radius ``r`` of a box's rounded edges [m] (default ``s/20``)."""
        return self.thickness / 20.0 if self.rounding is None else self.rounding

    @property
    def contact_radius(self) -> float:
        """Radius of curvature at a contact [m]: ``R = s/2`` (clump) or ``r`` (box); the
        radius of ``young``'s stiffness rule and the scale of the allowed floor overlap."""
        return self.radius if self.shape == "clump" else self.rounding_radius

    @property
    def poisson_ratio(self) -> float:
        """Poisson's ratio of a Hertz chain: ``poisson``, or 0.3 when not set."""
        return 0.3 if self.poisson is None else self.poisson

    @property
    def hertz_coefficient(self) -> float:
        """``K`` [N/m^{3/2}] of a Hertz point of two dominoes or a domino and the floor
        (``F = K delta^{3/2}``, ``K = 4/3 E* sqrt(r)``, ``1/E* = 2 (1 - nu^2) / E``);
        ValueError unless ``normal_law = "hertz"``."""
        if self.normal_law != "hertz":
            raise ValueError(f"normal_law = {self.normal_law!r}: no Hertz coefficient")
        modulus = self.young / (2.0 * (1.0 - self.poisson_ratio**2))
        return 4.0 / 3.0 * modulus * math.sqrt(self.rounding_radius)

    @property
    def base_layout(self) -> Base:
        """The clump's base: ``base``, or ``"one"`` when not set."""
        return self.base or "one"

    @property
    def restitution_pairs(self) -> tuple[float | None, float | None]:
        """(domino-domino, domino-floor) restitution; ``None`` = elastic."""
        dominoes = self.restitution_dominoes
        floor = self.restitution_floor
        return (
            self.restitution if dominoes is None else dominoes,
            self.restitution if floor is None else floor,
        )

    @property
    def box_points_per_pair(self) -> int:
        """Contact points carrying a box-box or a box-floor line contact: the two ends of
        the touching edge (a planar scene returns one, counted twice)."""
        return 2

    @property
    def spacing(self) -> float:
        """Clear gap ``d`` between neighbouring dominoes [m]."""
        return self.d_over_l * self.height

    @property
    def pitch(self) -> float:
        """Distance between neighbouring dominoes' axes, ``d + s`` [m]."""
        return self.spacing + self.thickness

    @property
    def n_column(self) -> int:
        """Spheres per column (default ``round(l/s)``: touching spheres)."""
        return self.spheres_per_column or self.n_column_touching

    @property
    def n_column_touching(self) -> int:
        return max(2, round(self.height / self.thickness))

    @property
    def n_across(self) -> int:
        """Columns across the width: 1 in 2D, ``max(1, round(w/s))`` in 3D."""
        return 1 if self.model == "2d" else max(1, round(self.width / self.thickness))

    @property
    def sphere_mass(self) -> float:
        """Mass of a reference bead ``rho 4/3 pi R^3`` [kg]."""
        return self.density * 4.0 / 3.0 * math.pi * self.radius**3

    @property
    def mass(self) -> float:
        """Domino mass [kg]: clump ``n_across * round(l/s)`` reference beads (see module
        doc); box ``rho l w s`` (2D and 3D alike)."""
        if self.shape == "box":
            return self.density * self.height * self.width * self.thickness
        return self.n_across * self.n_column_touching * self.sphere_mass

    @property
    def contact_stiffness(self) -> float:
        """Normal stiffness ``k_n`` of every contact [N/m] (see the class docstring)."""
        if self.kn is not None:
            return self.kn
        if self.young is not None:
            convention = "paper" if self.young_rule == "paper" else "contact"
            return float(
                contact_stiffness_from_material(self.contact_radius, self.young, convention)
            )
        ratio = 1e4 if self.stiffness_ratio is None else self.stiffness_ratio
        k = ratio * float(k_star(self.column_mass, self.height, self.g))
        # eq. 24: the two particles' springs k in series, k_n = k / 2 per contact; a box
        # carries it on the two points of a line contact, k_n = k / 4 per point
        return float(contact_stiffness(k, "paper")) / self.points_per_spring

    @property
    def column_mass(self) -> float:
        """Mass that defines ``k*`` [kg]: one column of spheres (the 2D clump domino), or
        the whole box."""
        if self.shape == "box":
            return self.mass
        return self.mass / self.n_across

    @property
    def points_per_spring(self) -> int:
        """Contact points sharing the paper's pair spring ``k/2``: 1 (clump: one sphere
        contact per column) or 2 (box: the two ends of the touching edge)."""
        return 1 if self.shape == "clump" else self.box_points_per_pair

    @property
    def pair_stiffness(self) -> float:
        """Normal stiffness between two dominoes [N/m]: clump, ``n_across`` columns touch
        in parallel, ``n_across * k_n`` (= ``k_n`` in 2D); box, the two points of the
        edge-face contact, ``2 k_n``."""
        if self.shape == "box":
            return self.box_points_per_pair * self.contact_stiffness
        return self.n_across * self.contact_stiffness

    @property
    def stiffness_over_kstar(self) -> float:
        """The paper's ``k/k*`` (``k = 2 k_n`` per column, or ``k = 4 k_n`` for a box
        whose two contact points share it; ``k* = m g / l`` with ``m = column_mass``)."""
        k = 2.0 * self.points_per_spring * self.contact_stiffness
        return k / float(k_star(self.column_mass, self.height, self.g))

    def with_(self, **changes) -> ChainParams:
        """A copy with some fields changed (validated again)."""
        if {"stiffness_ratio", "kn", "young"} & changes.keys():
            changes = {"stiffness_ratio": None, "kn": None, "young": None, **changes}
        if changes.get("normal_law", self.normal_law) == "linear":
            changes = {"poisson": None, **changes}
        if changes.get("shape", self.shape) != self.shape:
            # the options of the old shape do not carry over to the new one
            old = CLUMP_ONLY if self.shape == "clump" else BOX_ONLY
            changes = {**dict.fromkeys(old), **changes}
        return replace(self, **changes)


@dataclass(frozen=True)
class DominoShape:
    """Spheres of one upright domino in its own frame (pivot axis at the origin).

    ``centres`` shape (n, 3) [m], ``radii`` (n,) [m], ``density`` (n,) bead density
    [kg/m^3], ``bottom`` (n,) bool: member of the bottom layer (floor friction).
    x is along the chain, y across, z up; the floor is ``z = 0``.
    """

    centres: np.ndarray
    radii: np.ndarray
    density: np.ndarray
    bottom: np.ndarray

    @property
    def masses(self) -> np.ndarray:
        """Sphere masses [kg], shape (n,)."""
        return self.density * 4.0 / 3.0 * math.pi * self.radii**3

    @property
    def mass(self) -> float:
        return float(self.masses.sum())

    @property
    def centre_of_mass(self) -> np.ndarray:
        return self.masses @ self.centres / self.mass

    @property
    def pivot(self) -> int:
        """Index of the front-most bottom sphere: the one the domino tips over."""
        bottom = np.flatnonzero(self.bottom)
        return int(bottom[np.argmax(self.centres[bottom, 0])])

    @property
    def pivot_contact(self) -> np.ndarray:
        """Floor contact point below the pivot sphere, shape (3,) [m]."""
        return np.array([self.centres[self.pivot, 0], self.centres[self.pivot, 1], 0.0])

    def inertia_about_y(self, point) -> float:
        """Moment of inertia about the y axis through ``point`` [kg m^2]."""
        rel = self.centres - np.asarray(point, dtype=float)
        m = self.masses
        return float(np.sum(m * (0.4 * self.radii**2 + rel[:, 0] ** 2 + rel[:, 2] ** 2)))


def domino_shape(p: ChainParams) -> DominoShape:
    """The spheres of one domino for parameters ``p`` (see the module docstring)."""
    if p.shape != "clump":
        raise ValueError(
            f"shape = {p.shape!r}: domino_shape builds the clump of spheres (shape = 'clump');"
            " the box domino is domino_box"
        )
    r = p.radius
    nz = p.n_column
    # bead density keeping the mass of the touching column (resolution independence)
    rho = p.density * p.n_column_touching / nz
    z = np.linspace(r, p.height - r, nz)
    ny = p.n_across
    y = (np.arange(ny) - (ny - 1) / 2.0) * p.thickness
    cols = []
    for yi in y:
        c = np.zeros((nz, 3))
        c[:, 1] = yi
        c[:, 2] = z
        cols.append(c)
    centres = np.concatenate(cols)
    radii = np.full(centres.shape[0], r)
    density = np.full(centres.shape[0], rho)
    bottom = np.concatenate([np.arange(nz) == 0] * ny)
    if p.base_layout == "two":
        # replace each bottom sphere by two of radius R/2 at x = -+R/2, z = R/2, 4x denser
        keep = ~bottom
        pairs = []
        for yi in y:
            pairs.append([-r / 2, yi, r / 2])
            pairs.append([r / 2, yi, r / 2])
        centres = np.concatenate([np.array(pairs), centres[keep]])
        radii = np.concatenate([np.full(2 * ny, r / 2), radii[keep]])
        density = np.concatenate([np.full(2 * ny, 4.0 * rho), density[keep]])
        bottom = np.concatenate([np.ones(2 * ny, bool), np.zeros(int(keep.sum()), bool)])
    return DominoShape(centres=centres, radii=radii, density=density, bottom=bottom)


def chain_positions(p: ChainParams) -> np.ndarray:
    """x of each domino's axis [m], shape (N,): ``n (d + s)``."""
    return p.pitch * np.arange(p.n_dominoes)


@dataclass(frozen=True)
class Placement:
    """Where each domino actually stands: the seeded placement errors of ``ChainParams``.

    ``along`` (N,) [m] shift along the line (x), ``across`` (N,) [m] shift across it (y),
    ``yaw`` (N,) [rad] turn about the vertical, each uniform in +- its amplitude
    (``placement_along``, ``placement_across``, ``lateral_asymmetry``); ``push_factor``
    [-] scales the push of domino 0, ``1 + push_error N(0, 1)``.
    """

    along: np.ndarray
    across: np.ndarray
    yaw: np.ndarray
    push_factor: float


def placement(p: ChainParams) -> Placement:
    """The placement errors of chain ``p``, drawn from ``p.asymmetry_seed``.

    Each error has its own stream: the yaw from ``default_rng(seed)`` (as the lateral
    asymmetry always was, so its draws are unchanged), the along, across and push errors
    from ``default_rng([seed, 1])``, ``[seed, 2]``, ``[seed, 3]``; switching one error on
    does not change the others' draws. A zero amplitude draws nothing and gives zeros.
    """
    n = p.n_dominoes
    seed = p.asymmetry_seed

    def uniform(amplitude: float, stream: int | None) -> np.ndarray:
        if amplitude == 0.0:
            return np.zeros(n)
        rng = np.random.default_rng(seed if stream is None else [seed, stream])
        return amplitude * rng.uniform(-1.0, 1.0, n)

    push_factor = 1.0
    if p.push_error > 0.0:
        push_factor = 1.0 + p.push_error * np.random.default_rng([seed, 3]).standard_normal()
    return Placement(
        along=uniform(p.placement_along, 1),
        across=uniform(p.placement_across, 2),
        yaw=uniform(p.lateral_asymmetry, None),
        push_factor=float(push_factor),
    )


def place_domino(
    shape: DominoShape, x: float, yaw: float = 0.0, sink: float = 0.0, y: float = 0.0
) -> np.ndarray:
    """World sphere centres (n, 3) [m] of a domino at ``(x, y)``, turned by ``yaw`` [rad]
    about the vertical axis and lowered by ``sink`` [m] (static overlap with the floor)."""
    out = shape.centres @ yaw_matrix(yaw).T
    out[:, 0] += x
    if y != 0.0:
        out[:, 1] += y
    out[:, 2] -= sink
    return out


@dataclass(frozen=True)
class DominoBox:
    """One upright box domino in its own frame (axis at the origin, floor ``z = 0``).

    A uniform cuboid of thickness ``s`` (x, along the chain), width ``w`` (y) and height
    ``l`` (z) [m] whose edges are rounded with radius ``rounding`` r [m] (a core box of
    half-extents ``(s/2, w/2, l/2) - r`` swept by a sphere of radius r, ``dem.Scene.add_box``).
    x is along the chain, y across, z up.
    """

    half_extents: np.ndarray  # (3,) outer half-extents (s/2, w/2, l/2) [m]
    rounding: float
    mass: float

    @property
    def centre_of_mass(self) -> np.ndarray:
        """(3,) [m]: the box centre."""
        return np.array([0.0, 0.0, self.half_extents[2]])

    @property
    def pivot_point(self) -> np.ndarray:
        """(3,) [m] centre of the front bottom rounded edge (the axis it rolls about)."""
        r = self.rounding
        return np.array([self.half_extents[0] - r, 0.0, r])

    @property
    def pivot_contact(self) -> np.ndarray:
        """(3,) [m] floor contact below the front bottom edge: the point at rest in a
        rolling start."""
        return np.array([self.half_extents[0] - self.rounding, 0.0, 0.0])

    @property
    def inertia_cm_y(self) -> float:
        """Moment of inertia about the y axis through the centre [kg m^2],
        ``m (s^2 + l^2) / 12``."""
        a, _, c = self.half_extents
        return self.mass * (a**2 + c**2) / 3.0

    def inertia_about_y(self, point) -> float:
        """Moment of inertia about the y axis through ``point`` [kg m^2] (parallel axes)."""
        rel = np.asarray(point, dtype=float) - self.centre_of_mass
        return self.inertia_cm_y + self.mass * (rel[0] ** 2 + rel[2] ** 2)


def domino_box(p: ChainParams) -> DominoBox:
    """The box domino of parameters ``p`` (``shape = "box"``)."""
    half = np.array([p.thickness, p.width, p.height]) / 2.0
    return DominoBox(half_extents=half, rounding=p.rounding_radius, mass=p.mass)


def yaw_matrix(yaw: float) -> np.ndarray:
    """(3, 3) rotation by ``yaw`` [rad] about the vertical axis."""
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

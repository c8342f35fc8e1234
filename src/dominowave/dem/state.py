"""State of a DEM scene as struct-of-arrays (float64 NumPy arrays) and materials.

The compiled kernels receive these namedtuples; their fields are NumPy arrays that the
kernels update in place.  Conventions used throughout ``dominowave.dem``:

* SI units; world frame with gravity given explicitly (usually ``(0, 0, -g)``).
* Quaternions ``(w, x, y, z)`` rotate the body's principal frame into the world frame:
  ``x_world = x_com + R(q) @ x_body``.
* Body velocities are the leapfrog half-step values ``v(t - dt/2)`` between steps
  (as in YADE's NewtonIntegrator), except for ``fresh`` bodies (new or given a
  velocity) whose values are full-step ones; recorders report full-step values.  A held
  body is at rest, so its values are both (engine._release).
* A contact's second partner ``j >= 0`` is a sphere index, ``j < 0`` is the wall ``-(j + 1)``.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass

import numpy as np

from dominowave.checks import check_finite, check_in_range, check_nonnegative, check_positive

__all__ = [
    "Bodies",
    "Contacts",
    "Material",
    "MaterialTable",
    "Spheres",
    "Walls",
    "clump_mass_properties",
    "empty_contacts",
]

Bodies = namedtuple(
    "Bodies",
    [
        "pos",  # (nb, 3) centre of mass [m]
        "vel",  # (nb, 3) half-step velocity [m/s]
        "quat",  # (nb, 4) orientation (w, x, y, z)
        "rot",  # (nb, 3, 3) rotation matrix R(quat), body -> world
        "omega",  # (nb, 3) half-step angular velocity, world frame [rad/s]
        "angmom",  # (nb, 3) half-step angular momentum, world frame [kg m^2/s]
        "mass",  # (nb,) [kg]
        "inertia",  # (nb, 3) principal moments [kg m^2]
        "axis",  # (nb, 3) hinge-free rotation axis for rot_mode 2 (world unit vector)
        "axis_inertia",  # (nb,) moment of inertia about `axis` through the COM [kg m^2]
        "rot_mode",  # (nb,) int: 0 isotropic, 1 free aspherical, 2 fixed axis, 3 no rotation
        "blocked",  # (nb, 6) uint8: x y z rx ry rz blocked
        "held",  # (nb,) uint8: 1 while held in place until touched
        "fresh",  # (nb,) uint8: 1 if vel/omega hold full-step values (velocity-Verlet start)
        "release_time",  # (nb,) time the body was first released [s], nan otherwise
        "calm_since",  # (nb,) time since which the body has been slower than the sleep
        #   speed [s] (asleep: held with it set), nan otherwise (engine._sleep_and_wake)
        "vel_full",  # (nb, 3) full-step velocity v(t) of the last step [m/s]
        "omega_full",  # (nb, 3) full-step angular velocity of the last step [rad/s]
        "angmom_full",  # (nb, 3) full-step angular momentum of the last step [kg m^2/s]
        "force",  # (nb, 3) contact force of the current step [N]
        "torque",  # (nb, 3) contact torque about the COM, world frame [N m]
        "extent",  # (nb,) largest distance of a member sphere's centre from the COM (a
        #   box: its core's half-diagonal) [m]
        "pos_at_build",  # (nb, 3) COM at the last neighbour-list build [m]
        "quat_at_build",  # (nb, 4) orientation at the last neighbour-list build
    ],
)

Spheres = namedtuple(
    "Spheres",
    [
        "body",  # (ns,) int owner body
        "radius",  # (ns,) [m]
        "local",  # (ns, 3) centre in the owner's principal frame [m]
        "material",  # (ns,) int material id
        "pos",  # (ns, 3) world centre [m]; between list builds only for `listed` spheres
        "listed",  # (ns,) int64: ids of the spheres in the Verlet list, ascending
        "n_listed",  # (1,) int64: how many entries of `listed` are used
    ],
)

Walls = namedtuple("Walls", ["point", "normal", "material"])

# The contact properties (kn, kt, mu, cn) of a pair are computed from the materials when
# the pair enters the Verlet list and are kept while it stays listed: a change of the
# MaterialTable during a run reaches only pairs listed afterwards, so a script that edits
# it mid-run must edit Contacts.kn/kt/mu/cn of the listed pairs as well
# (docs/fig6/phi_f_study/switch.py does both).
MaterialTable = namedtuple(
    "MaterialTable",
    [
        "young",  # (nm,) Young's modulus E [Pa]; nan for a material given k_n
        "kn",  # (nm,) contact stiffness k_n [N/m]; nan for a material given E
        "kt_ratio",  # (nm,)
        "friction",  # (nm,)
        "restitution",  # (nm,)  1 = elastic
        "pair_friction",  # (nm, nm) symmetric: a pair's own mu (Scene.set_pair), nan: min rule
        "pair_restitution",  # (nm, nm) symmetric: a pair's own e, nan: min rule
        "poisson",  # (nm,) Poisson ratio (Hertz law)
        "hertz_damping",  # (nm, nm) Tsuji ratio alpha of each pair's restitution (laws/hertz.py)
        "rule",  # (1,) int: how a contact's k_n follows: material_pairs.RULE_PAPER, _YADE (from
        # young), RULE_GIVEN (kn)
        "shear_kinematics",  # (1,) int: 0 contact point, 1 yade (laws/tangential.py)
    ],
)

Contacts = namedtuple(
    "Contacts",
    [
        "n",  # (1,) int rows used (the spheres' Verlet list: -1 until first built)
        "i",  # (C,) sphere, or box (boxes.py)
        "j",  # (C,) partner sphere or box, or -(wall + 1)
        "key",  # (C,) int64 feature key of a box's point (shapes.cuboid); 0 for spheres
        "mult",  # (C,) how many points of the 3D body the row stands for (planar box: 2)
        "shear",  # (C, 3) Cundall-Strack shear displacement [m]
        "overlap",  # (C,) [m]: the row touches while it is positive; at the step a contact
        #   ends, the gap (<= 0); an idle pair of the Verlet list: 0 or the gap it ended at
        "vn",  # (C,) normal relative velocity (> 0 separating) at the last half step [m/s]
        "fn",  # (C,) normal force (elastic + dashpot) per point [N]
        "fn_viscous",  # (C,) its dashpot part [N]
        "kn",  # (C,) k_n [N/m]; Hertz: K of F = K delta^{3/2} [N/m^{3/2}]
        "kt",  # (C,) [N/m]
        "mu",  # (C,)
        "cn",  # (C,) dashpot [N s/m]; Hertz: c of -c delta^{1/4} v_n [N s/m^{5/4}]
        "point",  # (C, 3) contact point [m] of the last step in which the row touched or
        #   ended its contact, written by its driver before the bookkeeping reads it
        "normal",  # (C, 3) unit normal from i to j of that step
    ],
)
"""The one record of a contact point (contact_rows.py): the rows of every contact table --
the spheres' Verlet list (contact.py) and the rows of the boxes' box-box, box-wall and
box-sphere points (boxes.py) -- have these fields."""


def empty_contacts(capacity: int, n: int = 0) -> Contacts:
    """A table of ``capacity`` contact rows, ``n`` of them used (-1: a Verlet list never
    built), every row a single point (``mult`` 1)."""
    k = int(capacity)

    def column(name):
        if name in ("i", "j", "key"):
            return np.zeros(k, np.int64)
        if name in ("shear", "point", "normal"):
            return np.zeros((k, 3))
        return np.ones(k) if name == "mult" else np.zeros(k)

    return Contacts(n=np.array([n], np.int64), **{f: column(f) for f in Contacts._fields[1:]})


@dataclass(frozen=True)
class Material:
    """Contact material of a sphere, a box, a capsule or a wall.

    Parameters
    ----------
    density : float
        Mass density [kg/m^3] (the default mass of a body; ignored for walls).
    young : float, optional
        Young's modulus E [Pa]; the pair stiffness follows the scene's ``stiffness_rule``.
    kn : float, optional
        Contact normal stiffness [N/m]; pair value ``2 kn1 kn2 / (kn1 + kn2)``.
        Give exactly one of ``young`` and ``kn``.
    kt_ratio : float
        Tangential to normal stiffness ratio k_t / k_n.
    friction : float
        Coulomb coefficient mu >= 0; a contact uses min(mu_1, mu_2) (paper, section 3)
        unless the pair has its own value (Scene.set_pair).
    restitution : float, optional
        Normal restitution coefficient in (0, 1]; None means elastic (1).  A contact uses
        min(e_1, e_2) unless the pair has its own value (Scene.set_pair).
    poisson : float
        Poisson ratio nu in (-1, 0.5]; used by the Hertz normal law only
        (``Scene(normal_law="hertz")``: ``1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2``).
    """

    density: float = 1000.0
    young: float | None = None
    kn: float | None = None
    kt_ratio: float = 1.0
    friction: float = 0.0
    restitution: float | None = None
    poisson: float = 0.3

    def __post_init__(self):
        check_positive("density", self.density)
        if (self.young is None) == (self.kn is None):
            raise ValueError(
                f"Material needs exactly one of young and kn, got young = {self.young}, "
                f"kn = {self.kn}"
            )
        if self.young is not None:
            check_positive("young", self.young)
            check_finite("young", self.young)
        if self.kn is not None:
            check_positive("kn", self.kn)
            check_finite("kn", self.kn)
        check_nonnegative("kt_ratio", self.kt_ratio)
        check_nonnegative("friction", self.friction)
        if self.restitution is not None:
            check_in_range("restitution", self.restitution, 0.0, 1.0, hi_inclusive=True)
        check_in_range("poisson", self.poisson, -1.0, 0.5, hi_inclusive=True)


def sphere_mass(density, radius):
    """Mass of a solid sphere [kg] from density [kg/m^3] and radius [m]."""
    return density * 4.0 / 3.0 * math.pi * np.asarray(radius) ** 3


def clump_mass_properties(centres, radii, densities):
    """Mass, centre of mass, principal moments and axes of a rigid clump of spheres.

    Member masses are summed without subtracting overlaps (as YADE's clumps do by
    default).  Inertia tensor about the COM: sum of ``2/5 m_i R_i^2 1`` plus the parallel
    axis term ``m_i (|r_i|^2 1 - r_i r_i^T)``.

    Parameters
    ----------
    centres : (n, 3) array [m]
    radii, densities : (n,) arrays [m], [kg/m^3]

    Returns
    -------
    mass : float [kg]
    com : (3,) [m]
    moments : (3,) principal moments, ascending [kg m^2]
    axes : (3, 3) rotation matrix whose columns are the principal axes (det +1)
    inertia_tensor : (3, 3) world-frame inertia tensor about the COM [kg m^2]
    """
    centres = np.asarray(centres, dtype=float).reshape(-1, 3)
    m = sphere_mass(np.asarray(densities, dtype=float), radii)
    mass = float(m.sum())
    com = (m[:, None] * centres).sum(axis=0) / mass
    r = centres - com
    tensor = np.zeros((3, 3))
    for mi, ri, Ri in zip(m, r, np.asarray(radii, dtype=float), strict=True):
        tensor += 0.4 * mi * Ri**2 * np.eye(3) + mi * (ri @ ri * np.eye(3) - np.outer(ri, ri))
    # Products of inertia that are round-off of the centre-of-mass subtraction (a body
    # symmetric about the world axes) are set to zero: with two equal moments LAPACK
    # may otherwise return any rotated basis of their plane, different from one CPU to
    # another, and the body frame (hence every trajectory's round-off) with it.
    off_diagonal = ~np.eye(3, dtype=bool)
    tensor[off_diagonal & (np.abs(tensor) <= 1e-14 * np.abs(tensor).max())] = 0.0
    moments, axes = np.linalg.eigh(tensor)
    # Snap near-degenerate round-off so that symmetric bodies keep world-aligned axes.
    axes[np.abs(axes) < 1e-14] = 0.0
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1.0
    return mass, com, moments, axes, tensor


def quat_from_matrix(R):
    """Unit quaternion (w, x, y, z) of the rotation matrix ``R`` (Shepperd's method)."""
    R = np.asarray(R, dtype=float)
    tr = np.trace(R)
    candidates = np.array([tr, R[0, 0], R[1, 1], R[2, 2]])
    k = int(np.argmax(candidates))
    if k == 0:
        s = 2.0 * math.sqrt(1.0 + tr)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif k == 1:
        s = 2.0 * math.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = [(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif k == 2:
        s = 2.0 * math.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q / np.linalg.norm(q)

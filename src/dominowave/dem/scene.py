"""Building a scene: materials, spheres, clumps, walls -> a :class:`Simulation`."""

from __future__ import annotations

import math

import numpy as np

from dominowave.checks import check_finite, check_in_range, check_nonnegative, check_positive
from dominowave.dem.boxes import empty_boxes
from dominowave.dem.integrate import (
    ROT_AXIS,
    ROT_FREE,
    ROT_ISOTROPIC,
    ROT_NONE,
    check_blocked_spin,
)
from dominowave.dem.laws.hertz import LAW_HERTZ, NORMAL_LAWS, hertz_damping_table
from dominowave.dem.laws.tangential import SHEAR_CONTACT_POINT, SHEAR_YADE
from dominowave.dem.material_pairs import RULE_GIVEN, RULE_PAPER, RULE_YADE
from dominowave.dem.shapes.sphere import start_gaps
from dominowave.dem.simulation import Simulation
from dominowave.dem.state import (
    Bodies,
    Material,
    MaterialTable,
    Spheres,
    Walls,
    clump_mass_properties,
    quat_from_matrix,
)

__all__ = ["Scene", "parse_blocked"]

DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
RULES = {"paper": RULE_PAPER, "yade": RULE_YADE}
SHEAR_KINEMATICS = {"contact_point": SHEAR_CONTACT_POINT, "yade": SHEAR_YADE}


def parse_blocked(blocked) -> np.ndarray:
    """Blocked DOFs given as "y rx rz" (or a sequence of names) -> (6,) uint8 mask."""
    if isinstance(blocked, str):
        names = blocked.replace(",", " ").split()
    else:
        names = list(blocked)
    mask = np.zeros(6, np.uint8)
    for name in names:
        if name not in DOF_NAMES:
            raise ValueError(f"blocked = {name!r} is not a degree of freedom; use {DOF_NAMES}")
        mask[DOF_NAMES.index(name)] = 1
    return mask


def _rotation(name, value) -> np.ndarray:
    """A proper rotation matrix (3, 3), or a ValueError naming ``name``."""
    R = np.asarray(value, float)
    if R.shape != (3, 3) or not np.allclose(R.T @ R, np.eye(3), atol=1e-12):
        raise ValueError(f"{name} = {value!r} is not a 3 x 3 rotation matrix")
    if np.linalg.det(R) < 0:
        raise ValueError(f"{name} = {value!r} is a reflection (det -1)")
    return R


def _axis_frame(axis) -> np.ndarray:
    """The body axes (columns) of a body of symmetry axis ``axis`` (3,): axis 2 along it,
    axis 1 the part of world y normal to it (of world x if it is within 26 deg of y),
    axis 0 = 1 x 2."""
    v = _vector("axis", axis)
    if not np.any(v):
        raise ValueError(f"axis = {axis!r} has no direction; give a nonzero vector")
    v = v / np.abs(v).max()  # (no overflow in the norm of a huge vector)
    e2 = v / np.linalg.norm(v)
    ref = np.array([0.0, 1.0, 0.0]) if abs(e2[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = ref - (ref @ e2) * e2
    e1 /= np.linalg.norm(e1)
    return np.column_stack((np.cross(e1, e2), e1, e2))


def _vector(name, value):
    v = np.asarray(value, dtype=float).reshape(-1)
    if v.shape != (3,):
        raise ValueError(f"{name} = {value!r} must have 3 components")
    check_finite(name, v)
    return v


def _body(blocked, velocity, angular_velocity, held, **shape) -> dict:
    """The checked description of a body (``Scene.add_*``'s common arguments, and its
    shape's own entries)."""
    return {
        "blocked": parse_blocked(blocked),
        "velocity": _vector("velocity", velocity),
        "angular_velocity": _vector("angular_velocity", angular_velocity),
        "held": bool(held),
        **shape,
    }


class Scene:
    """Collects materials, bodies and walls; :meth:`build` returns a :class:`Simulation`.

    Parameters
    ----------
    gravity : (3,) [m/s^2]
    stiffness_rule : "paper" (k = pi R E per sphere, in series) or "yade"
        (k_n = 2 E1 R1 E2 R2 / (E1 R1 + E2 R2)); ignored for materials that give kn.
    shear_kinematics : what drives the tangential (Cundall-Strack) spring:
        "contact_point" (default) the relative velocity of the two material points at the
        contact point; "yade" YADE's ratcheting-free rate (the default of its
        Ig2_Sphere_Sphere_ScGeom and Ig2_Wall_Sphere_ScGeom): the sphere centres' relative
        velocity times ``(R_i + R_j) / (R_i + R_j - delta)`` plus the spins on the full
        radii -- for equal spheres and walls a tangential spring stiffer by that factor
        while it sticks (contact.py, docs/dem.md).
    normal_law : normal force of the box contacts: "linear" (default) ``k_n delta`` with
        the stiffness rule above, or "hertz" ``4/3 E* sqrt(R*) delta^{3/2}`` with the
        rounding radius as curvature and a Tsuji dashpot that gives the restitution set
        (laws/hertz.py); "hertz" needs every material to give ``young`` and a scene of boxes
        and walls (sphere contacts are linear).
    """

    def __init__(
        self,
        gravity=(0.0, 0.0, -9.81),
        stiffness_rule: str = "paper",
        shear_kinematics: str = "contact_point",
        normal_law: str = "linear",
    ):
        if stiffness_rule not in RULES:
            raise ValueError(f"stiffness_rule = {stiffness_rule!r} is not one of {tuple(RULES)}")
        if shear_kinematics not in SHEAR_KINEMATICS:
            raise ValueError(
                f"shear_kinematics = {shear_kinematics!r} is not one of {tuple(SHEAR_KINEMATICS)}"
            )
        if normal_law not in NORMAL_LAWS:
            raise ValueError(f"normal_law = {normal_law!r} is not one of {tuple(NORMAL_LAWS)}")
        self.gravity = _vector("gravity", gravity)
        self.stiffness_rule = stiffness_rule
        self.normal_law = normal_law
        self.shear_kinematics = shear_kinematics
        self.materials: list[Material] = []
        self._spheres: list[tuple] = []  # (body, centre, radius, material)
        self._bodies: list[dict] = []
        self._walls: list[tuple] = []  # (point, normal, material)
        self._pairs: dict[tuple[int, int], dict] = {}  # (a <= b) -> friction, restitution

    # ------------------------------------------------------------------ contents
    def add_material(self, material: Material) -> int:
        """Register a material; returns its id."""
        if not isinstance(material, Material):
            raise ValueError(f"material = {material!r} is not a Material")
        self.materials.append(material)
        return len(self.materials) - 1

    def set_pair(self, material_a: int, material_b: int, *, friction=None, restitution=None):
        """Give the contacts between two materials their own friction and/or restitution.

        Without it a contact uses ``min(mu_a, mu_b)`` and ``min(e_a, e_b)`` of the two
        materials; with it, e.g., dominoes and floor of one material can still have their
        own domino-domino and domino-floor values.  Symmetric (the pair (b, a) is the same
        pair); ``material_a == material_b`` sets the contacts of a material with itself;
        a later call overrides the values it gives and keeps the others.

        Parameters
        ----------
        material_a, material_b : material ids (:meth:`add_material`).
        friction : Coulomb coefficient of the pair, >= 0; None keeps the current value.
        restitution : normal restitution coefficient of the pair in (0, 1] (1: elastic);
            None keeps the current value.
        """
        a = self._material_id("material_a", material_a)
        b = self._material_id("material_b", material_b)
        if friction is not None:
            check_finite("friction", friction)
            check_nonnegative("friction", friction)
        if restitution is not None:
            check_in_range("restitution", restitution, 0.0, 1.0, hi_inclusive=True)
        entry = self._pairs.setdefault((min(a, b), max(a, b)), {})
        if friction is not None:
            entry["friction"] = float(friction)
        if restitution is not None:
            entry["restitution"] = float(restitution)

    def _material_id(self, name, value):
        k = int(value)
        if not 0 <= k < len(self.materials):
            raise ValueError(
                f"{name} = {value} is not a material id; valid range [0, {len(self.materials) - 1}]"
            )
        return k

    def add_wall(self, point, normal, material: int) -> int:
        """Infinite plane through ``point`` [m] with outward ``normal`` (bodies on its + side).

        The wall is one-sided: a sphere whose centre is at signed distance ``d < R`` from
        the plane overlaps it by ``R - d``.  Returns the wall id.
        """
        p = _vector("point", point)
        n = _vector("normal", normal)
        norm = np.linalg.norm(n)
        check_positive("|normal|", norm)
        self._walls.append((p, n / norm, self._material_id("material", material)))
        return len(self._walls) - 1

    def add_sphere(self, centre, radius, material: int, **options) -> int:
        """A free sphere; ``options`` as :meth:`add_clump`.  Returns the body id."""
        return self.add_clump([centre], [radius], material, **options)

    def add_clump(
        self,
        centres,
        radii,
        materials,
        *,
        blocked="",
        velocity=(0.0, 0.0, 0.0),
        angular_velocity=(0.0, 0.0, 0.0),
        held: bool = False,
    ) -> int:
        """A rigid clump of spheres; returns the body id.

        Parameters
        ----------
        centres : (n, 3) sphere centres in world coordinates [m]
        radii : (n,) or scalar [m]
        materials : (n,) material ids, or one id for every sphere
        blocked : DOFs to block, e.g. "y rx rz" (world axes x y z rx ry rz)
        velocity, angular_velocity : initial values (world frame) [m/s], [rad/s].  A
            blocked component keeps its value (YADE semantics) for spheres; an aspherical
            clump cannot turn about a blocked axis, so a nonzero blocked angular-velocity
            component is a ValueError for it (not silently zeroed).
        held : keep the body fixed until a non-held body touches it
        """
        centres = np.asarray(centres, dtype=float).reshape(-1, 3)
        n = centres.shape[0]
        if n == 0:
            raise ValueError("centres = [] must contain at least one sphere")
        check_finite("centres", centres)
        radii = np.broadcast_to(np.asarray(radii, dtype=float), (n,)).copy()
        body = len(self._bodies)
        for k, r in enumerate(radii):
            check_positive(f"radius of sphere {k} of body {body}", r)
        mats = np.broadcast_to(np.asarray(materials), (n,))
        mats = np.array([self._material_id("materials", m) for m in mats])
        self._bodies.append(_body(blocked, velocity, angular_velocity, held))
        for c, r, m in zip(centres, radii, mats, strict=True):
            self._spheres.append((body, c, r, m))
        return body

    def add_box(
        self,
        centre,
        half_extents,
        rounding,
        material: int,
        *,
        orientation=None,
        mass: float | None = None,
        inertia=None,
        blocked="",
        velocity=(0.0, 0.0, 0.0),
        angular_velocity=(0.0, 0.0, 0.0),
        held: bool = False,
    ) -> int:
        """A rigid rounded cuboid (dem/boxes.py, dem/shapes/cuboid.py); returns the body id.

        Parameters
        ----------
        centre : (3,) centre of the box [m] (its centre of mass).
        half_extents : (3,) outer half-extents (a, b, c) along the box axes [m]; the body
            is a core box of half-extents ``(a, b, c) - rounding`` swept by a sphere of
            radius ``rounding``.
        rounding : radius r of the rounded edges and corners [m], ``0 <= r < min(a, b, c)``.
        material : material id (its density gives the default mass).
        orientation : (3, 3) rotation whose columns are the box axes in the world frame
            (default: the world axes).  In a planar scene (blocked "y rx rz") box axis 1
            must be the world y axis.
        mass, inertia : the body's mass [kg] and principal moments (3,) about the box axes
            [kg m^2]; default those of a uniform cuboid of the outer size,
            ``m = 8 a b c rho``, ``I_x = m (b^2 + c^2) / 3`` (shapes.cuboid.cuboid_mass_properties).
        blocked, velocity, angular_velocity : as :meth:`add_clump`.
        held : keep the box fixed until a moving body touches it (as :meth:`add_clump`):
            while held it has no contact with other held boxes, nor with the walls until
            a moving box comes near (then it stands on them, as a free box at rest does),
            so a box held resting on the floor costs nothing until a moving box nears it.
        """
        from dominowave.dem.shapes.cuboid import cuboid_mass_properties

        centre = _vector("centre", centre)
        half = _vector("half_extents", half_extents)
        for k, h in enumerate(half):
            check_positive(f"half_extents[{k}] of body {len(self._bodies)}", h)
        check_in_range("rounding", rounding, 0.0, float(half.min()), lo_inclusive=True)
        mat = self._material_id("material", material)
        R = np.eye(3) if orientation is None else _rotation("orientation", orientation)
        return self._add_rounded(
            centre, half - float(rounding), rounding, mat, R,
            cuboid_mass_properties(half, self.materials[mat].density), mass=mass,
            inertia=inertia, blocked=blocked, velocity=velocity,
            angular_velocity=angular_velocity, held=held,
        )  # fmt: skip

    def add_capsule(
        self,
        centre,
        half_length: float,
        radius: float,
        material: int,
        *,
        axis=(0.0, 0.0, 1.0),
        **options,
    ) -> int:
        """A rigid capsule (a spherocylinder); returns the body id.

        The capsule is the rounded cuboid of :meth:`add_box` whose core is a segment: core
        half-extents ``(0, 0, c)`` along its axes, rounding ``r``.  Its contacts are the
        cuboid's (dem/shapes/cuboid.py; a core vertex of zero extent is one point), so it
        meets boxes, capsules, spheres and walls with the same law (the linear one: the
        Hertz law's radius of curvature is the boxes', ``Scene.build`` refuses capsules
        with it).

        Parameters
        ----------
        centre : (3,) centre of the capsule [m] (its centre of mass).
        half_length : half the length c of the axis segment between the centres of the two
            hemispherical caps [m], ``c > 0`` (a sphere is :meth:`add_sphere`'s); the
            capsule is ``2 (c + r)`` long.
        radius : radius r of the cylinder and the caps [m], ``r > 0``.
        material : material id (its density gives the default mass).
        axis : (3,) direction of the capsule's axis in the world frame (default z); it is
            body axis 2, and body axis 1 is the part of world y normal to it (of world x
            if the axis is within 26 deg of y): a capsule whose axis lies in the xz plane
            may move in a planar scene (blocked "y rx rz"), where it touches at one point,
            not along y.
        options : ``mass`` [kg] and ``inertia``, the principal moments (3,) about the body
            axes [kg m^2] (default those of a uniform solid capsule,
            shapes.cuboid.capsule_mass_properties); ``blocked``, ``velocity``,
            ``angular_velocity``, ``held``: as :meth:`add_box`.
        """
        from dominowave.dem.shapes.cuboid import capsule_mass_properties

        centre = _vector("centre", centre)
        body = len(self._bodies)
        check_in_range(f"half_length of body {body}", half_length, 0.0, math.inf)
        check_in_range(f"radius of body {body}", radius, 0.0, math.inf)
        mat = self._material_id("material", material)
        return self._add_rounded(
            centre, np.array([0.0, 0.0, float(half_length)]), radius, mat, _axis_frame(axis),
            capsule_mass_properties(half_length, radius, self.materials[mat].density),
            **options,
        )  # fmt: skip

    def _add_rounded(
        self, centre, core, rounding, mat, R, mass_properties, *, mass=None, inertia=None,
        blocked="", velocity=(0.0, 0.0, 0.0), angular_velocity=(0.0, 0.0, 0.0), held=False,
    ) -> int:  # fmt: skip
        """A rounded body at ``centre`` (3,) [m] of core half-extents ``core`` (3,) [m],
        rounding [m] and material id ``mat`` (checked by the caller), body axes the columns
        of ``R``; ``mass_properties`` the default (mass, moments) of its shape."""
        m_default, i_default = mass_properties
        if mass is not None:
            check_positive("mass", mass)
        moments = i_default if inertia is None else np.asarray(inertia, float).reshape(3)
        if inertia is not None:
            check_positive("inertia", moments)
        box = {
            "centre": centre,
            "core": np.asarray(core, float),
            "rounding": float(rounding),
            "material": mat,
            "axes": R,
            "mass": m_default if mass is None else float(mass),
            "moments": moments,
        }
        self._bodies.append(_body(blocked, velocity, angular_velocity, held, box=box))
        return len(self._bodies) - 1

    # ------------------------------------------------------------------ build
    def _material_table(self):
        given = [m.kn is not None for m in self.materials]
        if any(given) and not all(given):
            raise ValueError(
                "materials mix kn and young; give every material the same kind of stiffness"
            )
        nm = len(self.materials)
        pair = {"friction": np.full((nm, nm), np.nan), "restitution": np.full((nm, nm), np.nan)}
        for (a, b), values in self._pairs.items():
            for name, value in values.items():
                pair[name][a, b] = pair[name][b, a] = value
        restitution = np.array(
            [1.0 if m.restitution is None else m.restitution for m in self.materials]
        )
        hertz_damping = np.zeros((nm, nm))
        if NORMAL_LAWS[self.normal_law] == LAW_HERTZ:
            if any(given):
                raise ValueError(
                    "normal_law = 'hertz' needs Young's moduli: give every material young, not kn"
                )
            # the dashpot ratio of each pair's restitution (its own, else the min rule,
            # as material_pairs.pair_friction_restitution)
            e = np.where(
                np.isnan(pair["restitution"]),
                np.minimum.outer(restitution, restitution),
                pair["restitution"],
            )
            hertz_damping = hertz_damping_table(e)
        return MaterialTable(
            young=np.array([np.nan if m.young is None else m.young for m in self.materials], float),
            kn=np.array([np.nan if m.kn is None else m.kn for m in self.materials], float),
            kt_ratio=np.array([m.kt_ratio for m in self.materials], float),
            friction=np.array([m.friction for m in self.materials], float),
            restitution=restitution,
            pair_friction=pair["friction"],
            pair_restitution=pair["restitution"],
            poisson=np.array([m.poisson for m in self.materials], float),
            hertz_damping=hertz_damping,
            rule=np.array([RULE_GIVEN if all(given) else RULES[self.stiffness_rule]], np.int64),
            shear_kinematics=np.array([SHEAR_KINEMATICS[self.shear_kinematics]], np.int64),
        )

    def _bodies_and_spheres(self):
        nb = len(self._bodies)
        ns = len(self._spheres)
        sphere_body = np.array([s[0] for s in self._spheres], np.int64)
        centres = np.array([s[1] for s in self._spheres]).reshape(ns, 3)
        radii = np.array([s[2] for s in self._spheres], float)
        materials = np.array([s[3] for s in self._spheres], np.int64)
        density = np.array([self.materials[m].density for m in materials])
        z3 = lambda: np.zeros((nb, 3))  # noqa: E731
        bodies = Bodies(
            pos=z3(),
            vel=z3(),
            quat=np.zeros((nb, 4)),
            rot=np.zeros((nb, 3, 3)),
            omega=z3(),
            angmom=z3(),
            mass=np.zeros(nb),
            inertia=z3(),
            axis=z3(),
            axis_inertia=np.zeros(nb),
            rot_mode=np.zeros(nb, np.int64),
            blocked=np.zeros((nb, 6), np.uint8),
            held=np.zeros(nb, np.uint8),
            fresh=np.ones(nb, np.uint8),
            release_time=np.full(nb, np.nan),
            calm_since=np.full(nb, np.nan),
            vel_full=z3(),
            omega_full=z3(),
            angmom_full=z3(),
            force=z3(),
            torque=z3(),
            extent=np.zeros(nb),
            pos_at_build=z3(),
            quat_at_build=np.zeros((nb, 4)),
        )
        local = np.zeros((ns, 3))
        for b, spec in enumerate(self._bodies):
            members = np.flatnonzero(sphere_body == b)
            box = spec.get("box")
            if box is None:
                mass, com, moments, axes, tensor = clump_mass_properties(
                    centres[members], radii[members], density[members]
                )
            else:  # (principal axes: the box axes, even for a cube)
                mass, com, moments, axes = box["mass"], box["centre"], box["moments"], box["axes"]
                tensor = axes @ np.diag(moments) @ axes.T
            blocked = spec["blocked"]
            isotropic = box is None and np.ptp(moments) <= 1e-12 * moments.max()
            n_rot_blocked = int(blocked[3:].sum())
            if isotropic:
                mode, axes = ROT_ISOTROPIC, np.eye(3)
            elif n_rot_blocked == 0:
                mode = ROT_FREE
            elif n_rot_blocked == 2:
                mode = ROT_AXIS
                free = int(np.flatnonzero(blocked[3:] == 0)[0])
                bodies.axis[b, free] = 1.0
                bodies.axis_inertia[b] = tensor[free, free]
            elif n_rot_blocked == 3:
                mode = ROT_NONE
            else:
                raise ValueError(
                    f"blocked rotations of body {b} = {n_rot_blocked}: an aspherical clump may "
                    "block 0, 2 or 3 rotations (1 is not a hinge-free rigid motion)"
                )
            q = quat_from_matrix(axes)
            bodies.pos[b] = com
            bodies.quat[b] = q
            bodies.rot[b] = axes
            bodies.mass[b] = mass
            bodies.inertia[b] = moments
            bodies.rot_mode[b] = mode
            bodies.blocked[b] = blocked
            bodies.held[b] = spec["held"]
            v = spec["velocity"].copy()
            w = spec["angular_velocity"].copy()
            check_blocked_spin(b, w, mode, bodies.axis[b])
            if mode == ROT_AXIS:
                w = bodies.axis[b] * (w @ bodies.axis[b])  # (round-off of the check)
            if spec["held"]:
                v, w = np.zeros(3), np.zeros(3)
            bodies.vel[b] = v
            bodies.vel_full[b] = v
            bodies.omega[b] = w
            bodies.omega_full[b] = w
            if mode == ROT_ISOTROPIC:
                L = moments[0] * w
            elif mode == ROT_AXIS:
                L = bodies.axis_inertia[b] * w
            else:
                L = tensor @ w
            bodies.angmom[b] = L
            bodies.angmom_full[b] = L
            local[members] = (centres[members] - com) @ axes
            if box is None:
                bodies.extent[b] = np.linalg.norm(local[members], axis=1).max()
            else:
                bodies.extent[b] = np.linalg.norm(box["core"])
        spheres = Spheres(
            body=sphere_body,
            radius=radii,
            local=local,
            material=materials,
            pos=centres.copy(),
            listed=np.arange(ns, dtype=np.int64),
            n_listed=np.array([ns], np.int64),
        )
        return bodies, spheres

    def _walls_arrays(self):
        nw = len(self._walls)
        return Walls(
            point=np.array([w[0] for w in self._walls]).reshape(nw, 3),
            normal=np.array([w[1] for w in self._walls]).reshape(nw, 3),
            material=np.array([w[2] for w in self._walls], np.int64),
        )

    def build(
        self,
        dt: float | None = None,
        *,
        safety: float = 0.02,
        damping: float = 0.0,
        damp_gravity: bool = True,
        skin: float | None = None,
        record_pairs: bool | None = None,
        record_peak_force: bool = False,
        check_every: int = 100,
        overlap_tolerance: float = 1e-9,
        track_energy: bool = True,
        impact_speed: float | None = None,
        sleep_speed: float = 0.0,
        sleep_time: float = 0.0,
    ):
        """Freeze the scene into a :class:`~dominowave.dem.simulation.Simulation`.

        Parameters
        ----------
        dt : time step [s]; default ``safety * critical_dt``.  ValueError if above the
            critical step (timestep.py).
        safety : fraction of the critical step used when ``dt`` is None.  The default 0.02
            keeps the energy error of an elastic chain of spheres below ~1e-5 over 1e5
            steps; an isolated elastic collision errs by ~0.3 (omega dt)^4 in e
            (docs/dem.md), so larger values (up to ~0.3) are fine for many purposes.
        damping : YADE local damping coefficient in [0, 1).
        damp_gravity : damp gravity as well (YADE 2023.02a default).
        skin : Verlet skin [m]; default 0.3 x mean sphere radius (a scene of boxes only:
            of the boxes' smallest outer half-extent).
        record_pairs : body-pair statistics and the contact event log; default on for
            up to 2000 bodies.
        record_peak_force : also keep the peak normal force of a sphere contact or box
            contact point per body pair.
        check_every : steps between NaN / energy-runaway / kinetic-energy checks.
        overlap_tolerance : largest initial overlap allowed, relative to the radius.
        track_energy : keep the ledger of the energy dissipated by friction, dashpots and
            local damping (energy.py), so that the total energy is a conservation check.
            Off (as YADE's default ``O.trackEnergy = False``), a step skips the power of
            the contact forces (~10 % of a domino-chain step), the dissipated energies and
            the total read nan, and a blow-up is detected as growth of the mechanical
            energy instead.  The trajectory is the same either way.
        impact_speed : the largest normal speed [m/s] at which Hertz contacts are expected
            to close (``normal_law="hertz"``): the step estimate takes their stiffness
            ``3/2 K delta^{1/2}`` at the overlap such an impact reaches (timestep.py).
            Default: the fastest point of any body at start plus the free-fall speed
            ``sqrt(2 g H)`` over the height H the boxes span.
        sleep_speed : [m/s] boxes whose every point stays slower than this for
            ``sleep_time`` [s], with the moving boxes they touch, are put to sleep: held
            again, at no cost, until a moving body touches or drives them
            (engine._sleep_and_wake; docs/dem.md, "Sleeping boxes").  0 (default): never.
            Scenes of boxes only.
        """
        from dominowave.dem.timestep import critical_timestep

        if not self._bodies:
            raise ValueError("the scene has no bodies; add spheres, clumps or boxes before build")
        check_in_range("damping", damping, 0.0, 1.0, lo_inclusive=True)
        check_in_range("safety", safety, 0.0, 1.0, hi_inclusive=True)
        check_in_range("check_every", check_every, 1, math.inf, lo_inclusive=True)
        check_nonnegative("sleep_speed", sleep_speed)
        check_nonnegative("sleep_time", sleep_time)
        mats = self._material_table()
        bodies, spheres = self._bodies_and_spheres()
        walls = self._walls_arrays()
        if spheres.radius.size:
            _check_initial_overlaps(spheres, walls, overlap_tolerance)
            if sleep_speed > 0.0:
                raise ValueError(
                    f"sleep_speed = {sleep_speed} puts boxes to sleep, in scenes of boxes"
                    " only; this scene has spheres (leave sleep_speed = 0)"
                )
        boxes = self._boxes_arrays(spheres.body)
        if NORMAL_LAWS[self.normal_law] == LAW_HERTZ and np.any(boxes.half == 0.0):
            raise ValueError(
                "normal_law = 'hertz' takes a box's rounding as the curvature of its contacts,"
                " which a capsule's cap or side does not have; this scene has capsules (use"
                " normal_law = 'linear')"
            )
        if NORMAL_LAWS[self.normal_law] == LAW_HERTZ and spheres.radius.size:
            raise ValueError(
                "normal_law = 'hertz' is implemented for box and wall contacts only; "
                "this scene has spheres (use normal_law = 'linear')"
            )
        if impact_speed is None:
            impact_speed = self._expected_impact_speed(bodies, boxes)
        check_in_range("impact_speed", impact_speed, 0.0, math.inf, lo_inclusive=True)
        g = float(np.linalg.norm(self.gravity))
        with np.errstate(divide="ignore"):
            dt_crit = critical_timestep(bodies, spheres, walls, mats, boxes, impact_speed, g)
        if not math.isfinite(dt_crit):
            raise ValueError(
                "the step estimate is unbounded: no contact of this scene has a stiffness "
                "(Hertz contacts at rest without gravity and without a tangential spring); "
                "give impact_speed > 0"
            )
        if dt is None:
            dt = safety * dt_crit
        check_positive("dt", dt)
        if dt > dt_crit:
            raise ValueError(
                f"dt = {dt:.6g} s is above the critical time step estimate {dt_crit:.6g} s "
                "(timestep.critical_timestep: stiffest single contact and the contacts present "
                "at start); choose dt <= that, better safety * it (default safety 0.02)"
            )
        if skin is None:
            sizes = spheres.radius if spheres.radius.size else boxes.radius + boxes.half.min(axis=1)
            skin = 0.3 * float(sizes.mean())
        check_positive("skin", skin)
        n_bodies = bodies.mass.shape[0]
        if record_pairs is None:
            record_pairs = n_bodies <= 2000
        return Simulation(
            bodies,
            spheres,
            walls,
            mats,
            gravity=self.gravity,
            dt=float(dt),
            critical_dt=dt_crit,
            damping=float(damping),
            damp_gravity=bool(damp_gravity),
            skin=float(skin),
            record_pairs=bool(record_pairs),
            record_peak_force=bool(record_peak_force),
            check_every=int(check_every),
            track_energy=bool(track_energy),
            boxes=boxes,
            sleep_speed=sleep_speed,
            sleep_time=sleep_time,
        )

    def _expected_impact_speed(self, bodies, boxes):
        """Default ``impact_speed`` [m/s] of :meth:`build`: the fastest point of any body
        at start (``|v| + |omega| extent``) plus ``sqrt(2 |g| H)``, H the height the
        boxes' bounding spheres span along gravity."""
        speed = np.linalg.norm(bodies.vel_full, axis=1)
        speed += np.linalg.norm(bodies.omega_full, axis=1) * bodies.extent
        g = float(np.linalg.norm(self.gravity))
        height = 0.0
        if boxes.body.size and g > 0.0:
            up = -self.gravity / g
            reach = np.linalg.norm(boxes.half, axis=1) + boxes.radius
            z = bodies.pos[boxes.body] @ up
            height = float((z + reach).max() - (z - reach).min())
        return float(speed.max(initial=0.0) + math.sqrt(2.0 * g * height))

    def _boxes_arrays(self, sphere_body):
        specs = [(b, spec["box"]) for b, spec in enumerate(self._bodies) if "box" in spec]
        return empty_boxes(
            body=[b for b, _ in specs],
            half=[box["core"] for _, box in specs],
            radius=[box["rounding"] for _, box in specs],
            material=[box["material"] for _, box in specs],
            normal_law=NORMAL_LAWS[self.normal_law],
            sphere_body=sphere_body,
        )


def _check_initial_overlaps(spheres, walls, tolerance):
    """ValueError naming the first body that overlaps a wall or another body at start."""
    radius, body = spheres.radius, spheres.body
    height, i, j, gap = start_gaps(spheres, walls)
    for w, dist in enumerate(height):
        bad = np.flatnonzero(dist < radius * (1.0 - tolerance))
        if bad.size:
            s = bad[0]
            raise ValueError(
                f"body {body[s]} (sphere {s}) overlaps wall {w} at start by "
                f"{radius[s] - dist[s]:.6g} m; move it to the wall's positive side"
            )
    bad = np.flatnonzero(gap < -tolerance * np.minimum(radius[i], radius[j]))
    if bad.size:
        k = bad[0]
        raise ValueError(
            f"body {body[i[k]]} (sphere {i[k]}) overlaps body {body[j[k]]} (sphere {j[k]}) "
            f"at start by {-gap[k]:.6g} m"
        )

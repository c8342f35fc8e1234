"""Critical time step of the explicit scheme: an estimate from masses and stiffnesses.

Spring-mass estimate (the linear-contact analogue of YADE's PWaveTimeStep) for every body
``b`` and the stiffest contact ``k`` any of its spheres can form (with the stiffest partner
material present): a single contact at lever arm ``rho`` couples translation and
rotation, ``omega^2 = k (1/m + rho^2 / I)`` (the effective mass ``1/m_eff = 1/m +
rho^2/I`` of the contact point), so

    dt_crit = min_b 1 / sqrt(k_b (1/m_b + rho_b^2 / I_b)),

with, for a free aspherical clump, ``rho_b`` the largest distance of a sphere surface
from the COM and ``I_b`` the smallest principal moment (a bound over every axis, also
non-principal ones: ``|r x e|^2 <= |r|^2``, ``I_e >= I_min``); for a planar body the
distance from the fixed axis and the moment about it; for a single sphere the normal
force has no lever arm (``k_n / m``) and the tangential one has ``rho = R``
(``k_t (1/m + R^2/I) = 3.5 k_t / m``); bodies that cannot rotate: ``k/m``.

Leapfrog is stable for ``omega dt < 2``; ``dt_crit = 1/omega`` keeps a factor 2 for a
single contact and is the limit of a 1-D chain of contacts (``omega_max = 2 sqrt(k/m)``).
It is an ESTIMATE: a body pressed by ``N`` simultaneous contacts (a packing, a clump
lying on the floor) vibrates up to ``sqrt(N)`` faster, which the safety factor must
cover (YADE's GlobalStiffnessTimeStepper sums the stiffnesses of the current contacts of
each body instead).  Contacts present at start are counted: with ``K_b`` the sum of
their stiffnesses on body ``b``, Gershgorin's bound on the stiffness matrix gives
``omega^2 <= 2 K_b (1/m + rho^2/I)`` for bodies of similar mass, so ``dt_crit <=
sqrt(2 / (K_b (1/m + rho^2/I)))`` as well (exact for two equal spheres; a packing built
in contact gets a step ~sqrt(N/2) smaller).  E.g. 108 FCC spheres between 6 walls,
kt_ratio 1: unstable at 0.99 of the single-contact estimate alone, stable at 0.8; stable
at 0.99 of this one.  An unstable run is detected at run time (energy runaway or NaN)
and aborted.

A contact of a rounded cuboid x with a sphere s (boxes.py; linear: Hertz scenes hold
no spheres) couples the two bodies at one point: its mode has ``omega^2 = k (1/m_x^eff
+ 1/m_s^eff)``, the inverse effective masses at the point (boxes.inverse_mass_at) summed.
They are bounded as above: for the box ``1/m + rho^2/I`` with its outer half-diagonal
``rho`` and smallest moment (planar: about the axis), for a single sphere ``1/m`` along
the normal and ``1/m + R^2/I = 3.5/m`` across it, for a clump ``1/m + rho^2/I``; ``k``
the pair's normal and tangential stiffness (the box's rounding and the sphere's radius,
:func:`_box_sphere_omega2`).  The partner's mobility is counted here (box-box and
sphere-sphere contacts take each body against a fixed partner, within the factor 2):
a light ball on a box has the frequency of the pair, which the safety factor need not
cover.  Box-sphere contacts present at start enter the box's Gershgorin sum, with its
bound ``1/m + rho^2/I`` (``omega^2 <= K_x (1/m + rho^2/I) / 2`` with ``K_x`` the sum of
its sphere contacts' stiffnesses: a box resting on a bed of spheres); a sphere touches
few boxes, and each is covered by the pair's frequency.
"""

from __future__ import annotations

import numpy as np

from dominowave.dem.integrate import ROT_AXIS, ROT_NONE
from dominowave.dem.laws.hertz import LAW_HERTZ, hertz_coefficient, hertz_modulus
from dominowave.dem.material_pairs import pair_stiffness, particle_stiffness
from dominowave.dem.shapes.sphere import start_gaps

__all__ = ["critical_timestep"]


def critical_timestep(bodies, spheres, walls, mats, boxes=None, impact_speed=0.0, gravity=0.0):
    """Critical time step estimate [s] of the scene (see module docstring; rounded
    cuboids: :func:`_box_omega2`, whose Hertz contacts are taken at the overlap of an
    impact at ``impact_speed`` [m/s] or of resting under ``gravity`` [m/s^2]; box-sphere
    contacts: :func:`_box_sphere_omega2`)."""
    rule = int(mats.rule[0])
    omega2_boxes = 0.0
    if boxes is not None:
        omega2_boxes = _box_omega2(bodies, boxes, walls, mats, impact_speed, gravity)
    if spheres.radius.size == 0:
        return float(1.0 / np.sqrt(omega2_boxes))
    touching_boxes = []
    if boxes is not None and boxes.body.size:
        omega2_boxes = max(omega2_boxes, _box_sphere_omega2(bodies, spheres, boxes, mats))
        touching_boxes = _touching_box_spheres(bodies, spheres, boxes)

    def stiffest(ma, ra, mb, rb):
        """The larger of the normal and tangential stiffness of a pair [N/m]."""
        return max(_pair_stiffness(mats, ma, ra, mb, rb, t) for t in (0, 1))

    n_bodies = bodies.mass.shape[0]
    # one contact: the stiffest normal and tangential contact each body can form
    k_body = np.zeros((2, n_bodies))
    for t in (0, 1):
        k_sphere = np.array(
            [
                _particle_stiffness(mats, m, r, t)
                for m, r in zip(spheres.material, spheres.radius, strict=True)
            ]
        )
        k_partner = float(k_sphere.max())
        k_max = np.array([pair_stiffness(k, k_partner, rule) for k in k_sphere])
        for w_mat in walls.material:
            k_wall = np.array(
                [
                    pair_stiffness(k, _particle_stiffness(mats, w_mat, r, t), rule)
                    for k, r in zip(k_sphere, spheres.radius, strict=True)
                ]
            )
            k_max = np.maximum(k_max, k_wall)
        np.maximum.at(k_body[t], spheres.body, k_max)
    k_n, k_t = k_body
    inv_mass = 1.0 / bodies.mass
    coupling = _rotational_coupling(bodies, spheres)
    single = (bodies.rot_mode != ROT_NONE) & (np.bincount(spheres.body, minlength=n_bodies) == 1)
    omega2 = np.where(
        single,  # a sphere: the normal force has no lever arm
        np.maximum(k_n * inv_mass, k_t * (inv_mass + coupling)),
        np.maximum(k_n, k_t) * (inv_mass + coupling),
    )
    # several contacts at start: Gershgorin bound on the stiffness-sum
    k_sum = np.zeros(n_bodies)
    for i, j in _touching_pairs(spheres, walls):
        partner = walls.material[-j - 1] if j < 0 else spheres.material[j]
        r_j = spheres.radius[i] if j < 0 else spheres.radius[j]
        k = stiffest(spheres.material[i], spheres.radius[i], partner, r_j)
        k_sum[spheres.body[i]] += k
        if j >= 0:
            k_sum[spheres.body[j]] += k
    # box-sphere contacts at start, on the box (a box on a bed of spheres); a sphere
    # touches few boxes, each covered by the pair's own frequency (_box_sphere_omega2),
    # which the half-sum would only make more conservative for a single ball on a box
    k_box = np.zeros(n_bodies)
    for x, s in touching_boxes:
        k = stiffest(boxes.material[x], boxes.radius[x], spheres.material[s], spheres.radius[s])
        k_box[boxes.body[x]] += k
    omega2 = np.maximum(omega2, 0.5 * k_sum * (inv_mass + coupling))
    for x, b in enumerate(boxes.body if touching_boxes else ()):
        omega2_boxes = max(omega2_boxes, 0.5 * k_box[b] * _box_inverse_mass(bodies, boxes, x))
    return float(1.0 / np.sqrt(max(omega2.max(), omega2_boxes)))


def _particle_stiffness(mats, material, radius, tangential):
    """Normal (or, ``tangential``, tangential) stiffness [N/m] of one side of a contact
    point of ``material`` at the sphere or rounding radius [m], as
    material_pairs.material_pair takes it: particle_stiffness by the scene's rule, times
    the material's kt_ratio for the tangential one."""
    k = particle_stiffness(mats.young[material], mats.kn[material], radius, int(mats.rule[0]))
    return k * mats.kt_ratio[material] if tangential else k


def _pair_stiffness(mats, ma, ra, mb, rb, tangential):
    """Normal (or tangential) stiffness [N/m] of a contact point between material ``ma``
    at radius ``ra`` [m] and ``mb`` at ``rb``: its two sides (:func:`_particle_stiffness`)
    combined by the scene's rule (material_pairs.pair_stiffness)."""
    ka = _particle_stiffness(mats, ma, ra, tangential)
    kb = _particle_stiffness(mats, mb, rb, tangential)
    return pair_stiffness(ka, kb, int(mats.rule[0]))


def _box_omega2(bodies, boxes, walls, mats, impact_speed=0.0, gravity=0.0):
    """Largest ``omega^2`` [1/s^2] of the rounded cuboids: a face resting on a face or
    wall, its 4 corners in contact at once (Gershgorin, as above:
    ``omega^2 <= 4 k (1/m + rho^2/I)``), with ``k`` the stiffest normal or tangential
    point stiffness the box can form (another box's material or a wall's), ``rho`` its
    outer half-diagonal and ``I`` its smallest moment (planar: about the axis).

    A Hertz point (laws/hertz.py) has the tangent stiffness ``3/2 K delta^{1/2}``, largest at
    the largest overlap: that of an impact at ``impact_speed`` v with the box's whole
    mass, ``(5 m v^2 / (4 K))^{2/5}``, or of resting on 4 points, ``(m g / (4 K))^{2/3}``.
    """
    if boxes.body.size == 0:
        return 0.0
    hertz = boxes.normal_law[0] == LAW_HERTZ

    def normal(m, r, pm, pr, mass):
        if not hertz:
            return _pair_stiffness(mats, m, r, pm, pr, False)
        E = hertz_modulus(mats.young[m], mats.poisson[m], mats.young[pm], mats.poisson[pm])
        K = hertz_coefficient(E, 2.0 * r * pr / (r + pr))  # (the largest R* of the pair)
        impact = (1.25 * mass * impact_speed**2 / K) ** 0.4
        rest = (0.25 * mass * gravity / K) ** (2.0 / 3.0)
        return 1.5 * K * np.sqrt(max(impact, rest))

    omega2 = 0.0
    # (the kinds of partner, each once: a long chain has one kind of box)
    boxes_kinds = set(zip(boxes.material.tolist(), boxes.radius.tolist(), strict=True))
    wall_kinds = set(walls.material.tolist())
    for x, b in enumerate(boxes.body):
        m, r = boxes.material[x], boxes.radius[x]
        partners = boxes_kinds | {(w, r) for w in wall_kinds}  # (a wall: the box's radius)
        k = max(
            max(
                normal(m, r, pm, pr, bodies.mass[b]),
                _pair_stiffness(mats, m, r, pm, pr, True),
            )
            for pm, pr in partners
        )
        omega2 = max(omega2, 4.0 * k * _box_inverse_mass(bodies, boxes, x))
    return omega2


def _box_inverse_mass(bodies, boxes, x):
    """``1/m + rho^2/I`` [1/kg] of box x: a bound on its inverse effective mass at any
    point of its surface along any direction (``rho`` its outer half-diagonal, ``I`` its
    smallest moment; planar: about the axis; 0 coupling if it cannot rotate)."""
    b = boxes.body[x]
    rho = np.linalg.norm(boxes.half[x]) + boxes.radius[x]
    if bodies.rot_mode[b] == ROT_NONE:
        coupling = 0.0
    elif bodies.rot_mode[b] == ROT_AXIS:
        coupling = rho**2 / bodies.axis_inertia[b]
    else:
        coupling = rho**2 / bodies.inertia[b].min()
    return 1.0 / bodies.mass[b] + coupling


def _box_sphere_omega2(bodies, spheres, boxes, mats):
    """Largest ``omega^2`` [1/s^2] of a box-sphere contact (module docstring):
    ``max(k_n (w_x + w_s^n), k_t (w_x + w_s^t))`` over every box x and sphere s of the
    scene, ``w_x`` the box's bound (:func:`_box_inverse_mass`), ``w_s`` that of the
    sphere's body along (n) and across (t) the normal, ``k_n``, ``k_t`` the pair's
    stiffnesses (material_pairs.particle_stiffness with the box's rounding and the sphere's
    radius, material_pairs.pair_stiffness, as material_pairs.material_pair)."""
    n_bodies = bodies.mass.shape[0]
    inv_mass = 1.0 / bodies.mass
    coupling = _rotational_coupling(bodies, spheres)
    single = (bodies.rot_mode != ROT_NONE) & (np.bincount(spheres.body, minlength=n_bodies) == 1)
    across = (inv_mass + coupling)[spheres.body]
    along = np.where(single, inv_mass, inv_mass + coupling)[spheres.body]  # (a ball: no lever)
    w_box = np.array([_box_inverse_mass(bodies, boxes, x) for x in range(boxes.body.size)])
    omega2 = 0.0
    # (per kind of box and of sphere: their material and radius set the stiffness)
    for mb, rb in set(zip(boxes.material, boxes.radius, strict=True)):
        wx = w_box[(boxes.material == mb) & (boxes.radius == rb)].max()
        for ms, rs in set(zip(spheres.material, spheres.radius, strict=True)):
            sel = (spheres.material == ms) & (spheres.radius == rs)
            kn = _pair_stiffness(mats, mb, rb, ms, rs, False)
            kt = _pair_stiffness(mats, mb, rb, ms, rs, True)
            omega2 = max(omega2, kn * (wx + along[sel].max()), kt * (wx + across[sel].max()))
    return omega2


def _touching_box_spheres(bodies, spheres, boxes):
    """(box, sphere) pairs in contact at start: the sphere within its radius plus the
    box's rounding of the core box (shapes.cuboid.point_box_distance), among the spheres
    within the box's bounding sphere."""
    from scipy.spatial import cKDTree

    from dominowave.dem.shapes.cuboid import point_box_distance

    tree = cKDTree(spheres.pos)
    out = []
    for x, b in enumerate(boxes.body):
        reach = np.linalg.norm(boxes.half[x]) + boxes.radius[x] + float(spheres.radius.max())
        for s in tree.query_ball_point(bodies.pos[b], reach):
            if spheres.body[s] == b:
                continue
            c = spheres.pos[s]
            d = point_box_distance(bodies.pos[b], bodies.rot[b], boxes.half[x], c[0], c[1], c[2])
            if d[0] <= boxes.radius[x] + spheres.radius[s]:
                out.append((x, int(s)))
    return out


def _rotational_coupling(bodies, spheres):
    """``rho^2 / I`` [1/kg] of each body (0 if it cannot rotate); see module docstring."""
    r = np.einsum("sij,sj->si", bodies.rot[spheres.body], spheres.local)  # world offsets
    along = (r * bodies.axis[spheres.body]).sum(axis=1)  # (0 unless planar)
    arm = np.sqrt(np.maximum((r**2).sum(axis=1) - along**2, 0.0)) + spheres.radius
    rho = np.zeros(bodies.mass.shape[0])
    np.maximum.at(rho, spheres.body, arm)
    planar = bodies.rot_mode == ROT_AXIS
    inertia = np.where(planar, bodies.axis_inertia, bodies.inertia.min(axis=1))
    rotating = bodies.rot_mode != ROT_NONE
    return np.where(rotating, rho**2 / np.where(rotating, inertia, 1.0), 0.0)


def _touching_pairs(spheres, walls):
    """(sphere, partner) pairs in contact at start; partner = sphere or -(wall + 1)."""
    height, i, j, gap = start_gaps(spheres, walls)
    out = []
    for w, dist in enumerate(height):
        out += [(int(s), -w - 1) for s in np.flatnonzero(dist <= spheres.radius)]
    keep = gap <= 0.0
    out += [(int(a), int(b)) for a, b in zip(i[keep], j[keep], strict=True)]
    return out

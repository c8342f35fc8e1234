"""Critical time step of the explicit scheme.

Spring-mass estimate (the linear-contact analogue of YADE's PWaveTimeStep): for every
body ``b`` and the stiffest contact ``k_max`` any of its spheres can form (normal or
tangential, with the stiffest partner material present),

    dt_crit = min_b min( sqrt(m_b / k_max),  min_a sqrt(I_a,b / (k_max rho_a,b^2)) ),

with ``rho_a,b`` the largest distance of a sphere surface from the principal axis ``a``
through the COM (the lever arm of a contact force; it matters for slender clumps, whose
rocking mode is stiffer than their translation).  Planar bodies (rotation about one
fixed axis) use the moment of inertia about that axis.

Leapfrog is stable for ``omega dt < 2``; a chain of equal masses has ``omega_max =
2 sqrt(k/m)``, so ``sqrt(m/k)`` is the stability limit of a 1-D chain of contacts and a
conservative bound for a single contact (limit ``sqrt(2 m/k)``).  A body pressed by
``N`` simultaneous contacts (a clump lying on the floor) has ``omega`` larger by up to
``sqrt(N)``: the safety factor must cover that.
"""

from __future__ import annotations

import numpy as np

from dominowave.dem.contact import pair_stiffness, particle_stiffness
from dominowave.dem.integrate import ROT_AXIS, ROT_NONE

__all__ = ["critical_timestep"]


def critical_timestep(bodies, spheres, walls, mats):
    """Critical time step [s] of the scene (see module docstring)."""
    rule = int(mats.rule[0])
    given = bool(mats.given_kn[0])

    def stiffest(material, radius):
        k = particle_stiffness(mats.stiffness[material], radius, given, rule)
        return k * max(1.0, mats.kt_ratio[material])

    k_sphere = np.array(
        [stiffest(m, r) for m, r in zip(spheres.material, spheres.radius, strict=True)]
    )
    k_partner = float(k_sphere.max())
    k_max = np.array([pair_stiffness(k, k_partner, given, rule) for k in k_sphere])
    for w_mat in walls.material:
        k_wall = np.array(
            [
                pair_stiffness(k, stiffest(w_mat, r), given, rule)
                for k, r in zip(k_sphere, spheres.radius, strict=True)
            ]
        )
        k_max = np.maximum(k_max, k_wall)
    n_bodies = bodies.mass.shape[0]
    k_body = np.zeros(n_bodies)
    np.maximum.at(k_body, spheres.body, k_max)
    dt = float(np.sqrt(bodies.mass / k_body).min())
    # rocking about each principal axis a: lever arm = distance of a sphere surface
    # from the axis, inertia I_a (or the fixed-axis inertia of planar bodies)
    u = spheres.local
    for a in range(3):
        arm = np.sqrt(np.maximum((u**2).sum(axis=1) - u[:, a] ** 2, 0.0)) + spheres.radius
        rho = np.zeros(n_bodies)
        np.maximum.at(rho, spheres.body, arm)
        inertia = bodies.inertia[:, a].copy()
        planar = bodies.rot_mode == ROT_AXIS
        inertia[planar] = bodies.axis_inertia[planar]
        rotating = bodies.rot_mode != ROT_NONE
        if np.any(rotating):
            dt = min(dt, float(np.sqrt(inertia / (k_body * rho**2))[rotating].min()))
    return dt

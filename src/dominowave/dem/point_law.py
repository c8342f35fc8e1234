"""The contact law of one contact point of rounded bodies (a pure per-point function).

Every contact point of a rounded cuboid -- with a box, a wall (boxes.box_forces) or a
sphere (box_sphere.box_sphere_forces) -- obeys the same law; the drivers find the point
(geometry, shear history carried by its key) and the kinematics of the two bodies there,
:func:`point_law` turns them into the force and the point's new state, and the drivers
apply the force and keep the state.  In the jax-md style (Schoenholz & Cubuk, NeurIPS
2020): scalars in, scalars out, nothing read from or written to the bodies.

With ``n`` the unit normal from body i to body j, ``delta`` > 0 the overlap, ``dv`` the
velocity of the material point of j minus that of i, ``v_n = dv . n`` (< 0 approaching):

* normal force on j along n, linear (contact.linear_normal_force): ``F_n = k_n delta -
  c_n v_n``, the overlap at an onset averaged over the kick interval
  (contact.onset_averaged_overlap); or Hertz (hertz.hertz_normal): ``K delta^{3/2} - c
  delta^{1/4} v_n``.  The dashpot sees the normal velocity at mid-step, extrapolated from
  the last two half steps, ``3/2 v_n - 1/2 v_n'`` (a fresh point: ``v_n``).
* tangential force on j, ``-k_t u``: the shear displacement ``u`` of the last step
  carried into the new tangent plane and turned by half the step's spin of the two
  bodies about the normal (contact.rotate_shear), plus the tangential relative
  displacement of the step, ``(dv - v_n n) dt`` (none at the first step: the initial
  configuration has no history), then held to the Coulomb cone ``k_t |u| <= mu k_n
  delta`` (contact.cundall_strack; Cundall & Strack, Geotechnique 29, 47 (1979)).

The dashpot coefficient of a point is fixed at its onset (:func:`onset_dashpot`) from
the effective mass of the two bodies at the point along the normal (the rigid-body
impulse response; Stronge, Impact Mechanics (2000) ch. 5):
linear ``c_n = 2 zeta sqrt(m_eff k_n)`` for the restitution set
(contact.viscous_coefficient), Hertz ``c = alpha sqrt(m_eff K)`` (Tsuji, Tanaka & Ishida,
Powder Technol. 71, 239 (1992)).
"""

from __future__ import annotations

import math

from numba import njit

from dominowave.dem.contact import (
    cundall_strack,
    onset_averaged_overlap,
    rotate_shear,
    viscous_coefficient,
)
from dominowave.dem.hertz import hertz_normal

__all__ = ["onset_dashpot", "point_law"]


@njit(cache=True, error_model="numpy", inline="always")
def onset_dashpot(kn, restitution, alpha, inverse_mass, hertz):
    """Dashpot coefficient of a new contact point: linear law ``c_n`` [N s/m] giving the
    ``restitution`` to a single-point impact of effective mass ``1 / inverse_mass`` [kg]
    on the spring ``kn`` [N/m] (contact.viscous_coefficient); Hertz law (``kn`` = K
    [N/m^{3/2}]) ``alpha sqrt(m_eff K)`` [N s/m^{5/4}] with the Tsuji ratio ``alpha``."""
    if hertz:
        return alpha * math.sqrt(kn / inverse_mass)
    return viscous_coefficient(restitution, 1.0 / inverse_mass, kn)


@njit(cache=True, error_model="numpy", inline="always")
def point_law(
    overlap, n0, n1, n2, dv0, dv1, dv2, spin, u0, u1, u2, vn_old, fresh,
    kn, kt, mu, cn, dt, first_step, hertz,
):  # fmt: skip
    """Force and new state of one contact point (module docstring).

    In: ``overlap`` delta [m] > 0; the unit normal ``n`` (i to j); ``dv`` [m/s] the
    velocity of j's material point minus i's; ``spin`` [rad/s] the sum of the two bodies'
    angular velocities along n; the point's state of the last step: shear ``u`` [m] (zero
    for a fresh point) and normal velocity ``vn_old`` [m/s]; ``fresh`` (the point has no
    last step); the point's constants ``kn`` [N/m] (Hertz: K [N/m^{3/2}]), ``kt`` [N/m],
    ``mu``, ``cn`` (:func:`onset_dashpot`); the step ``dt`` [s]; ``first_step`` (no
    tangential increment); ``hertz`` (the normal law).

    Returns ``(fn, fn_viscous, vn, u0, u1, u2, released, f0, f1, f2)``: the normal force
    on j [N] and its dashpot part, the normal velocity [m/s] (the next step's
    ``vn_old``), the new shear [m], the energy ``k_t (|u_old|^2 - |u|^2) / 2`` [J] the
    tangential spring released this step (by slip; the ledger's friction entry), and the
    force on j ``f = F_n n - k_t u`` [N] (on i: ``-f``), all at the point."""
    stored = u0 * u0 + u1 * u1 + u2 * u2
    vn = dv0 * n0 + dv1 * n1 + dv2 * n2
    u0, u1, u2 = rotate_shear(u0, u1, u2, n0, n1, n2, 0.5 * spin * dt)
    increment = 0.0 if first_step else dt
    u0 += (dv0 - vn * n0) * increment
    u1 += (dv1 - vn * n1) * increment
    u2 += (dv2 - vn * n2) * increment
    vn_dashpot = vn if fresh else 1.5 * vn - 0.5 * vn_old
    if hertz:  # (no onset correction: force and dashpot vanish at zero overlap)
        fn_elastic, fn_viscous = hertz_normal(kn, cn, overlap, vn_dashpot)
    else:
        weight, overlap_kick = onset_averaged_overlap(overlap, vn, dt, fresh)
        fn_elastic = kn * overlap_kick
        fn_viscous = -cn * vn_dashpot * weight
    u0, u1, u2 = cundall_strack(u0, u1, u2, kt, mu, fn_elastic)
    stored -= u0 * u0 + u1 * u1 + u2 * u2
    fn = fn_elastic + fn_viscous
    return (
        fn, fn_viscous, vn, u0, u1, u2, 0.5 * kt * stored,
        fn * n0 - kt * u0, fn * n1 - kt * u1, fn * n2 - kt * u2,
    )  # fmt: skip

"""The contact law of one contact point (a pure per-point function).

Every contact point of the engine -- sphere-sphere and sphere-wall (contact.compute_forces),
box-box, box-wall and box-sphere (boxes.box_forces, in one table) -- obeys this one law;
the drivers find the point (geometry, shear history carried by its pair or feature key)
and the kinematics of the two bodies there, :func:`point_law` turns them into the force
and the point's new state, and the drivers apply the force and keep the state.  In the
jax-md style (Schoenholz & Cubuk, NeurIPS 2020): scalars in, scalars out, nothing read
from or written to the bodies.  (The planar kernel of the sphere
driver, contact.compute_forces_planar, passes the out-of-plane components as zero.)

With ``n`` the unit normal from body i to body j, ``delta`` > 0 the overlap, ``dv`` the
velocity of the material point of j minus that of i, ``v_n = dv . n`` (< 0 approaching):

* normal force on j along n, linear (laws.linear.linear_normal_force): ``F_n = k_n delta -
  c_n v_n``, the overlap at an onset averaged over the kick interval
  (laws.linear.onset_averaged_overlap); or Hertz (laws.hertz.hertz_normal): ``K delta^{3/2} - c
  delta^{1/4} v_n``.  The dashpot sees the normal velocity at mid-step, extrapolated from
  the last two half steps, ``3/2 v_n - 1/2 v_n'`` (a fresh point: ``v_n``).
* tangential force on j, ``-k_t u``: the shear displacement ``u`` of the last step
  carried into the new tangent plane and turned about the normal by the angle the
  driver gives, half the step's spin of the two bodies about it (laws.tangential.rotate_shear),
  plus the tangential relative displacement of the step, ``(s - (s . n) n) dt`` (none at
  the first step: the initial configuration has no history), then held to the Coulomb
  cone ``k_t |u| <= mu k_n delta`` (laws.tangential.cundall_strack; Cundall & Strack,
  Geotechnique 29, 47 (1979)).  The shear rate ``s`` is ``dv`` at the contact point, or
  for spheres with YADE's shear kinematics its rate (laws.tangential.yade_shear_velocity).

The dashpot coefficient of a point is fixed at its onset (:func:`onset_dashpot`) from
the effective mass of the two bodies at the point along the normal (the rigid-body
impulse response; Stronge, Impact Mechanics (2000) ch. 5):
linear ``c_n = 2 zeta sqrt(m_eff k_n)`` for the restitution set
(laws.linear.viscous_coefficient), Hertz ``c = alpha sqrt(m_eff K)`` (Tsuji, Tanaka & Ishida,
Powder Technol. 71, 239 (1992)).
"""

from __future__ import annotations

import math

from dominowave.dem.compiled import inline_kernel
from dominowave.dem.laws.hertz import hertz_normal
from dominowave.dem.laws.linear import (
    linear_normal_force,
    onset_averaged_overlap,
    viscous_coefficient,
)
from dominowave.dem.laws.tangential import cundall_strack, rotate_shear

__all__ = ["onset_dashpot", "point_energy", "point_law", "point_power"]


@inline_kernel(python_entry=True)
def onset_dashpot(kn, restitution, alpha, inverse_mass, hertz):
    """Dashpot coefficient of a new contact point: linear law ``c_n`` [N s/m] giving the
    ``restitution`` to a single-point impact of effective mass ``1 / inverse_mass`` [kg]
    on the spring ``kn`` [N/m] (laws.linear.viscous_coefficient); Hertz law (``kn`` = K
    [N/m^{3/2}]) ``alpha sqrt(m_eff K)`` [N s/m^{5/4}] with the Tsuji ratio ``alpha``.
    Zero between two immovable bodies (``inverse_mass`` 0): there is no impact to damp."""
    if not inverse_mass > 0.0:
        return 0.0
    if hertz:
        return alpha * math.sqrt(kn / inverse_mass)
    return viscous_coefficient(restitution, 1.0 / inverse_mass, kn)


@inline_kernel()
def point_law(
    overlap, n0, n1, n2, dv0, dv1, dv2, s0, s1, s2, turn, u0, u1, u2, vn_old, fresh,
    kn, kt, mu, cn, dt, first_step, hertz,
):  # fmt: skip
    """Force and new state of one contact point (module docstring).

    In: ``overlap`` delta [m] > 0; the unit normal ``n`` (i to j); ``dv`` [m/s] the
    velocity of j's material point minus i's; ``s`` [m/s] the relative velocity that
    drives the shear (``dv``, or YADE's rate); ``turn`` [rad] the angle the shear turns
    about n this step (half the step's spin of the two bodies about it); the point's
    state of the last step: shear ``u`` [m] (zero for a fresh point) and normal velocity
    ``vn_old`` [m/s]; ``fresh`` (the point has no last step); the point's constants ``kn``
    [N/m] (Hertz: K [N/m^{3/2}]), ``kt`` [N/m], ``mu``, ``cn`` (:func:`onset_dashpot`);
    the step ``dt`` [s]; ``first_step`` (no tangential increment); ``hertz`` (the normal
    law).

    Returns ``(fn, fn_viscous, vn, u0, u1, u2, released, f0, f1, f2)``: the normal force
    on j [N] and its dashpot part, the normal velocity [m/s] (the next step's
    ``vn_old``), the new shear [m], the energy ``k_t (|u_old|^2 - |u|^2) / 2`` [J] the
    tangential spring released this step (by slip; the ledger's friction entry), and the
    force on j ``f = F_n n - k_t u`` [N] (on i: ``-f``), all at the point."""
    stored = u0 * u0 + u1 * u1 + u2 * u2
    vn = dv0 * n0 + dv1 * n1 + dv2 * n2
    sn = s0 * n0 + s1 * n1 + s2 * n2  # (= vn where s is dv)
    u0, u1, u2 = rotate_shear(u0, u1, u2, n0, n1, n2, turn)
    increment = 0.0 if first_step else dt
    u0 += (s0 - sn * n0) * increment
    u1 += (s1 - sn * n1) * increment
    u2 += (s2 - sn * n2) * increment
    vn_dashpot = vn if fresh else 1.5 * vn - 0.5 * vn_old
    if hertz:  # (no onset correction: force and dashpot vanish at zero overlap)
        fn_elastic, fn_viscous = hertz_normal(kn, cn, overlap, vn_dashpot)
    else:
        weight, overlap_kick = onset_averaged_overlap(overlap, vn, dt, fresh)
        fn_elastic, fn_viscous = linear_normal_force(kn, cn, overlap_kick, vn_dashpot, weight)
    u0, u1, u2 = cundall_strack(u0, u1, u2, kt, mu, fn_elastic)
    stored -= u0 * u0 + u1 * u1 + u2 * u2
    fn = fn_elastic + fn_viscous
    return (
        fn, fn_viscous, vn, u0, u1, u2, 0.5 * kt * stored,
        fn * n0 - kt * u0, fn * n1 - kt * u1, fn * n2 - kt * u2,
    )  # fmt: skip


@inline_kernel()
def point_energy(kn, kt, overlap, u0, u1, u2, hertz):
    """Elastic energies [J] stored at a contact point of overlap ``delta`` [m] > 0 and
    shear ``u`` [m]: the normal spring's, ``k_n delta^2 / 2`` (linear) or ``2/5 K
    delta^{5/2}`` (Hertz, ``kn`` = K; laws/hertz.py), and the tangential spring's,
    ``k_t |u|^2 / 2``."""
    if hertz:
        normal = 0.4 * kn * overlap**2.5
    else:
        normal = 0.5 * kn * overlap**2
    return normal, 0.5 * kt * (u0 * u0 + u1 * u1 + u2 * u2)


@inline_kernel()
def point_power(fd, n0, n1, n2, dv0, dv1, dv2, kt, u0, u1, u2):
    """Power [W] of the forces on the bodies at a contact point whose relative velocity
    (j minus i) is ``dv`` [m/s]: of the dashpot force ``F_d n`` (``fd`` [N], unit normal
    ``n``), ``F_d n . dv``, and of the tangential force ``-k_t u`` (``kt`` [N/m], shear
    ``u`` [m]), ``-k_t u . dv``.  Returns ``(viscous, friction)``."""
    return fd * (n0 * dv0 + n1 * dv1 + n2 * dv2), -kt * (u0 * dv0 + u1 * dv1 + u2 * dv2)

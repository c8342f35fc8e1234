"""The tangential law of a contact point: a Coulomb-limited shear spring (pure per-point
functions).

Elastic shear displacement ``u`` accumulated from the tangential relative velocity,
``F_t = -k_t u``, Coulomb limit ``|F_t| <= mu k_n delta``; on sliding ``u`` is shortened
to the limit (:func:`cundall_strack`; Cundall & Strack, Geotechnique 29, 47 (1979);
YADE's Law2_ScGeom_FrictPhys_CundallStrack).  When the contact frame moves, ``u`` is
projected onto the new tangent plane with its length kept, then turned about the normal
by the mean spin of the two bodies (:func:`rotate_shear`; as YADE's ScGeom::rotate, but
norm preserving).

Shear kinematics (a scene's ``shear_kinematics``): the shear increment is the tangential
relative velocity of the two material points at the contact point times dt
(:data:`SHEAR_CONTACT_POINT`, the default: Cundall & Strack 1979; the rate whose product
with the contact force is the power the force does on the bodies), or, for spheres,
YADE's "ratcheting-free" rate (:data:`SHEAR_YADE`, :func:`yade_shear_velocity`:
Ig2_Sphere_Sphere_ScGeom's avoidGranularRatcheting and Ig2_Wall_Sphere_ScGeom's noRatch,
both on by default in YADE; McNamara, Garcia-Rojo & Herrmann, Phys. Rev. E 77, 031304
(2008)), which scales the relative velocity of the sphere centres by ``alpha = (R_i +
R_j) / (R_i + R_j - delta)`` and turns the spins on the full radii.  For two equal
spheres and a sphere on a wall the YADE rate is ``alpha`` times the contact-point rate:
the same rolling condition, the same force while sliding, but a tangential spring
``alpha`` times stiffer while sticking.  docs/dem.md gives the comparison with YADE.
"""

from __future__ import annotations

import math

from dominowave.dem.compiled import inline_kernel

__all__ = [
    "SHEAR_CONTACT_POINT",
    "SHEAR_YADE",
    "cundall_strack",
    "rotate_shear",
    "yade_shear_velocity",
]

# shear kinematics: what drives the shear displacement (module docstring)
SHEAR_CONTACT_POINT = 0  # relative velocity of the material points at the contact point
SHEAR_YADE = 1  # YADE's avoidGranularRatcheting / noRatch rate (yade_shear_velocity)


@inline_kernel()
def rotate_shear(u0, u1, u2, n0, n1, n2, spin):
    """The shear displacement ``u`` carried into the new tangent plane (normal ``n``, norm
    kept), then turned about the normal by the angle ``spin`` [rad] (mean rotation of the
    two bodies about it).  Returns the new ``u`` [m]."""
    un = u0 * n0 + u1 * n1 + u2 * n2
    if un != 0.0:  # (at an axis-aligned wall the shear stays exactly in its plane: un == 0)
        old2 = u0 * u0 + u1 * u1 + u2 * u2
        u0 -= un * n0
        u1 -= un * n1
        u2 -= un * n2
        new2 = u0 * u0 + u1 * u1 + u2 * u2
        if new2 > 0.0:
            scale = math.sqrt(old2 / new2)
            u0 *= scale
            u1 *= scale
            u2 *= scale
    if spin != 0.0:
        # Rodrigues for a vector perpendicular to n: u cos + (n x u) sin, with the Cayley
        # (rational) cos/sin of the small angle: an exact rotation (norm kept) by
        # 2 atan(spin/2) = spin (1 - spin^2/12 + ...), without trigonometric calls
        h = 0.25 * spin * spin
        cos_ = (1.0 - h) / (1.0 + h)
        sin_ = spin / (1.0 + h)
        x = n1 * u2 - n2 * u1
        y = n2 * u0 - n0 * u2
        z = n0 * u1 - n1 * u0
        u0 = u0 * cos_ + x * sin_
        u1 = u1 * cos_ + y * sin_
        u2 = u2 * cos_ + z * sin_
    return u0, u1, u2


@inline_kernel(python_entry=True)
def yade_shear_velocity(dc0, dc1, dc2, a0, a1, a2, n0, n1, n2, rsum, overlap):
    """YADE's relative velocity for the shear increment (its normal part is removed by the
    caller), j minus i [m/s]: ``alpha (v_cj - v_ci) - (R_i w_i + R_j w_j) x n`` with
    ``alpha = (R_i + R_j) / (R_i + R_j - delta)`` (ScGeom::getIncidentVel with
    avoidGranularRatcheting; McNamara et al., Phys. Rev. E 77, 031304 (2008)).

    ``dc`` = ``v_cj - v_ci`` the relative velocity of the two sphere *centres* (a clump
    member's centre moves with ``v + w x (x_s - x_b)``), ``a`` = ``R_i w_i + R_j w_j``
    [m rad/s], ``n`` the unit normal from i to j, ``rsum`` = ``R_i + R_j`` [m] (a wall
    takes the sphere's radius: ``2 R_i``), ``overlap`` = delta [m].

    The material points at the contact point move with ``v_ci + w_i x (R_i - delta/2) n``
    and ``v_cj - w_j x (R_j - delta/2) n``; for ``R_i = R_j`` (and a wall) the YADE rate is
    exactly ``alpha`` times their relative velocity.
    """
    alpha = rsum / (rsum - overlap)
    return (
        alpha * dc0 - (a1 * n2 - a2 * n1),
        alpha * dc1 - (a2 * n0 - a0 * n2),
        alpha * dc2 - (a0 * n1 - a1 * n0),
    )


@inline_kernel()
def cundall_strack(u0, u1, u2, kt, mu, fn_elastic):
    """Coulomb limit of the tangential spring: the shear displacement after this step.

    ``u`` [m] is the trial displacement ``t`` (last step's displacement carried into the
    new tangent plane plus this step's tangential increment); while ``kt |t| <= mu
    fn_elastic`` it sticks and is returned unchanged, otherwise it slides and is shortened
    to ``b = t mu fn_elastic / (kt |t|)`` (YADE's Law2_ScGeom_FrictPhys_CundallStrack).  The
    tangential force on partner j is ``-kt u``.

    The energy this removes is booked by the driver as the work of the tangential forces
    that is not stored in the springs (contact_rows.rows_power), not as YADE's plastic
    work ``(|t| - |b|) kt |b|`` per step: the latter pairs the force of one instant with a
    displacement over the step and lets the balance drift at first order in dt.
    """
    tt = u0 * u0 + u1 * u1 + u2 * u2
    limit = mu * fn_elastic  # (>= 0)
    if kt * kt * tt > limit * limit:  # |trial force| > limit, without a sqrt when sticking
        s = limit / (kt * math.sqrt(tt))
        return u0 * s, u1 * s, u2 * s
    return u0, u1, u2

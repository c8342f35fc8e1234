"""The linear normal law of a contact point: a spring-dashpot (pure per-point functions).

``F_n = k_n delta - c_n v_n`` on partner j along the unit normal n from i to j (delta the
overlap, ``v_n`` the normal relative velocity, < 0 approaching): Cundall & Strack,
Geotechnique 29, 47 (1979), with YADE's Law2_ScGeom_FrictPhys_CundallStrack and a viscous
dashpot whose coefficient gives a restitution (:func:`viscous_coefficient`).  The leapfrog
kick applies the force at t_n over a whole step, so a contact that starts or ends inside
a step gets the overlap averaged over the part in contact at its onset
(:func:`onset_averaged_overlap`) and the impulse the last kick missed at its end
(:func:`end_impulse`).  The Hertz law is laws/hertz.py; laws/point.py combines either
with the tangential law (laws/tangential.py) into the law of one contact point.
"""

from __future__ import annotations

import math

from numba import njit

from dominowave.dem.compiled import inline_kernel

__all__ = ["end_impulse", "linear_normal_force", "onset_averaged_overlap", "viscous_coefficient"]


@njit(cache=True, error_model="numpy")
def viscous_coefficient(restitution, m_eff, kn):
    """Dashpot coefficient c_n [N s/m] giving restitution ``e`` for a linear spring-dashpot.

    Damped oscillator ``m x'' + c x' + k x = 0`` released at zero overlap, contact ended when
    the overlap returns to zero: ``e = exp(-zeta pi / sqrt(1 - zeta^2))`` with
    ``zeta = c / (2 sqrt(m k))``, i.e. ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``
    (e.g. Schwager & Poeschel, Phys. Rev. E 75, 051304 (2007), eq. 2-5; Antypov & Elliott,
    EPL 94, 50004 (2011)).
    """
    if restitution >= 1.0:
        return 0.0
    log_e = math.log(restitution)
    zeta = -log_e / math.sqrt(math.pi * math.pi + log_e * log_e)
    return 2.0 * zeta * math.sqrt(m_eff * kn)


@inline_kernel()
def onset_averaged_overlap(overlap, vn, dt, new_contact):
    """Contact onset inside a kick interval: the overlap averaged over the interval.

    Leapfrog applies the force at t_n for the whole interval [t_n - dt/2, t_n + dt/2].
    When a contact starts inside it, the force law has a kink (elastic) or a jump
    (dashpot) there and the midpoint rule errs by O(dt^2) resp. O(dt) per collision.
    With the overlap linear in time, ``delta(t) = delta_n + |vn| (t - t_n)`` (``vn < 0``
    approaching), the part of the interval spent in contact is ``w = 1/2 + delta_n / (|vn|
    dt)``, including the part of the preceding interval whose step saw no overlap, and the
    average elastic overlap is ``|vn| dt w^2 / 2``.  Returns ``(w, averaged overlap)``.

    Only a *new* contact that approaches is modified: a contact that has been closed
    before is never changed while it stays closed (it may turn around near zero overlap
    without opening); its end is corrected afterwards, see :func:`end_impulse`.
    """
    ramp = -vn * dt
    if not new_contact or overlap >= ramp:  # (also every vn >= 0: ramp <= 0 < overlap)
        return 1.0, overlap
    w = 0.5 + overlap / ramp
    return w, 0.5 * ramp * w * w


@inline_kernel()
def linear_normal_force(kn, cn, overlap, vn, weight):
    """Normal force [N] of the linear spring-dashpot on partner j along ``n`` (minus on
    i), as its elastic part ``k_n delta`` and its dashpot part ``-c_n v_n w``.

    ``kn`` [N/m] the contact stiffness (material_pairs.pair_stiffness, the paper's eqs. 22-24),
    ``cn`` [N s/m] the dashpot (:func:`viscous_coefficient`), ``overlap`` delta [m] the
    overlap acting over the kick (at an onset its average over the kick interval,
    :func:`onset_averaged_overlap`), ``vn`` [m/s] the normal relative velocity (j minus i,
    < 0 approaching), ``weight`` w the fraction of the kick interval in contact (1 but at
    an onset).  Cundall & Strack (1979), Geotechnique 29:47; YADE's
    Law2_ScGeom_FrictPhys_CundallStrack with a viscous dashpot.  Returns ``(elastic,
    dashpot)``.
    """
    return kn * overlap, -cn * vn * weight


@inline_kernel(python_entry=True)
def end_impulse(last_overlap, gap, kn, cn, dt):
    """Normal force [N] for one kick that supplies the impulse missed when a contact ended.

    Called at the first step ``n+1`` that sees no overlap (``gap = delta_{n+1} <= 0``)
    after the overlap ``delta_n > 0`` of step ``n``.  The overlap fell linearly,
    ``delta(t) = delta_n - v (t - t_n)`` with ``v = (delta_n - delta_{n+1}) / dt``, and
    reached zero at ``t_n + r dt``, ``r = delta_n / (v dt)`` in (0, 1].  The exact
    elastic impulse from ``t_n - dt/2`` on is ``kn v dt^2 (r + 1/2)^2 / 2``; the kick of
    step n applied ``kn delta_n dt``; the difference ``kn v dt^2 (r - 1/2)^2 / 2 >= 0`` is
    applied now.  The dashpot (``-cn v`` while in contact) missed ``-cn v dt (r - 1/2)``.
    Returns ``(elastic force, dashpot force)`` = missed impulses / dt.  The impulse
    arrives one kick late, which leaves the momentum transfer of the collision exact to
    the order of the linear overlap model (the restitution error stays fourth order).
    """
    ramp = last_overlap - gap
    if ramp <= 0.0 or last_overlap <= 0.0:
        return 0.0, 0.0
    r = last_overlap / ramp
    return 0.5 * kn * ramp * (r - 0.5) ** 2, -cn * ramp / dt * (r - 0.5)

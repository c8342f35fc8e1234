"""Hertz normal law for the contact points of rounded bodies (pure per-point functions).

Two elastic bodies whose surfaces have radii ``R_1``, ``R_2`` at the contact press on
each other with (Hertz 1882; Johnson, Contact Mechanics (1985) sec. 4.2)

    F = 4/3 E* sqrt(R*) delta^{3/2} = K delta^{3/2},
    1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2,   1/R* = 1/R_1 + 1/R_2 (a plane: 1/R = 0),

and store the elastic energy ``2/5 K delta^{5/2}``.  A contact point of a rounded cuboid
is taken as such a contact, with the rounding radius as the curvature (the paper's
future-work item 2): a rounded vertex on a wall ``R* = r``, any point between two boxes
``R* = 2 r_i r_j / (r_i + r_j)`` (= r for equal radii).  For equal radii that is exact for
a rounded vertex (a sphere) on a face and for two rounded edges (cylinders) crossing at a
right angle (Johnson sec. 4.2: crossed cylinders act as a sphere on a plane); edges
crossing at an angle theta have ``R* = r / |sin theta|`` (and an elliptic contact), so
the law is stiffer than Hertz's there by up to ``|sin theta|^{-1/2}``.  Where the touching
surface is not curved in two directions it is an approximation: a rounded *edge* resting
on a face is a cylinder on a plane, a line contact whose force grows nearly linearly with
the overlap (Johnson sec. 4.3); the engine represents it, as in the linear law, by the
two points at the ends of the edge, each a sphere-plane Hertz contact.

Dashpot (Tsuji, Tanaka & Ishida, Powder Technol. 71, 239 (1992)):
``F_d = -alpha sqrt(m_eff K) delta^{1/4} v_n``.  With ``delta = L x``, ``t = (L/v) tau``
and ``L = (m_eff v^2 / K)^{2/5}`` a head-on impact at speed v becomes

    x'' = -x^{3/2} - alpha x^{1/4} x',   x(0) = 0, x'(0) = 1,

free of v, m_eff and K: the restitution ``e = -x'(tau_end)`` depends on ``alpha`` alone
(a velocity-independent restitution, the reason for the 1/4 power).
:func:`hertz_damping_ratio` finds ``alpha(e)`` by integrating this equation.  Force and
dashpot vanish at zero overlap, so the law needs no onset or end corrections (the linear
law's laws.linear.onset_averaged_overlap and laws.linear.end_impulse).

Closed forms of an elastic impact at speed v (tests): the largest overlap
``delta_max = (5 m_eff v^2 / (4 K))^{2/5} = (15 m_eff v^2 / (16 E* sqrt(R*)))^{2/5}``, the
largest force ``K delta_max^{3/2}``, the contact duration ``2.943 delta_max / v =
2.87 (m_eff^2 / (R* E*^2 v))^{1/5}`` (Johnson sec. 11.4).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from dominowave.checks import check_in_range
from dominowave.dem.compiled import inline_kernel

__all__ = [
    "LAW_HERTZ",
    "LAW_LINEAR",
    "NORMAL_LAWS",
    "hertz_coefficient",
    "hertz_damping_ratio",
    "hertz_modulus",
    "hertz_normal",
    "hertz_restitution",
]

LAW_LINEAR = 0
LAW_HERTZ = 1
NORMAL_LAWS = {"linear": LAW_LINEAR, "hertz": LAW_HERTZ}


@inline_kernel(python_entry=True)
def hertz_modulus(young_1, poisson_1, young_2, poisson_2):
    """Effective modulus E* [Pa] of two materials (Young's moduli [Pa], Poisson ratios)."""
    return 1.0 / ((1.0 - poisson_1**2) / young_1 + (1.0 - poisson_2**2) / young_2)


@inline_kernel(python_entry=True)
def hertz_coefficient(modulus, radius):
    """``K = 4/3 E* sqrt(R*)`` [N/m^{3/2}] of ``F = K delta^{3/2}`` (E* [Pa], R* [m])."""
    return 4.0 / 3.0 * modulus * math.sqrt(radius)


@inline_kernel()
def hertz_normal(K, c, overlap, vn):
    """Elastic and dashpot normal force [N] of one Hertz point:
    ``K delta^{3/2}`` and ``-c delta^{1/4} v_n`` (c = alpha sqrt(m_eff K), Tsuji 1992)
    at overlap ``delta`` [m] > 0 and normal relative velocity ``v_n`` [m/s]."""
    root = math.sqrt(overlap)
    return K * overlap * root, -c * math.sqrt(root) * vn


def hertz_restitution(alpha):
    """Restitution of a head-on impact under the Tsuji dashpot of ratio ``alpha`` >= 0:
    ``-x'`` when ``x'' = -x^{3/2} - alpha x^{1/4} x'`` from (0, 1) returns to x = 0
    (0 if it never does: overdamped)."""

    def rhs(_, y):
        x = max(y[0], 0.0)
        return [y[1], -(x**1.5) - alpha * x**0.25 * y[1]]

    def back(_, y):
        return y[0]

    back.terminal = True
    back.direction = -1
    # (start just inside, on the undamped branch x = tau, to leave the event at 0 behind)
    tau0 = 1e-9
    sol = solve_ivp(rhs, (tau0, 50.0), [tau0, 1.0], events=back, rtol=1e-11, atol=1e-14)
    if not sol.t_events[0].size:
        return 0.0
    return float(-sol.y_events[0][0][1])


def hertz_damping_ratio(restitution):
    """Tsuji dashpot ratio ``alpha`` giving the restitution ``e`` in (0, 1] (module
    docstring); 0 for e = 1.  (About a second per value: each is solved once per process.)"""
    check_in_range("restitution", restitution, 0.0, 1.0, hi_inclusive=True)
    return _damping_ratio(float(restitution))


@functools.lru_cache(maxsize=256)
def _damping_ratio(restitution):
    if restitution >= 1.0:
        return 0.0
    hi = 1.0
    while hertz_restitution(hi) > restitution:
        hi *= 2.0
        if hi > 1e3:
            raise ValueError(f"no Tsuji dashpot ratio up to 1e3 gives restitution = {restitution}")
    return brentq(lambda a: hertz_restitution(a) - restitution, 0.0, hi, xtol=1e-13, rtol=1e-12)


def hertz_damping_table(restitution):
    """``alpha`` (nm, nm) for the restitution (nm, nm) of every material pair."""
    restitution = np.asarray(restitution, float)
    out = np.empty_like(restitution)
    for index, e in np.ndenumerate(restitution):
        out[index] = hertz_damping_ratio(e)
    return out

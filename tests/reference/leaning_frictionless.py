"""The frictionless leaning train from its geometry and two conservation laws.

Independent of ``dominowave.theory.leaning``, which eliminates the contact forces of
Newton-Euler's equations one domino at a time: here no force appears.

* **Geometry.** Each domino is a rectangle turning about its front-bottom edge. The
  tilt of domino ``k`` is the root (``brentq``) of the signed distance of its top-front
  corner from the back face of domino ``k - 1``, both placed by rotation matrices.
* **Velocities.** ``Phi_k = d theta_k / d theta_0`` by central differences of those
  roots, ``S = sum Phi_k^2``, so the train's kinetic energy is ``I S theta_0'^2 / 2``.
* **Collision.** Frictionless contact impulses do no work on any motion the
  constraints allow, so the generalised momentum along the new train's one motion is
  kept: ``omega+ S(0) = omega- (S(0) - 1)`` (the struck domino rested before).
* **Leaning phase.** Energy: ``I S(theta) u(theta) / 2 + V(theta)`` is constant.
* **Steady state.** With both, ``omega+^2 = (2 E / I) (S(0) - 1) / S(0)``, ``E`` the
  energy a domino releases between standing and its rest tilt in the train. The fall
  time is the Gauss-Legendre quadrature of ``1 / sqrt(u)`` over ``0 .. beta`` (smooth:
  ``u > 0`` on the closed interval).

Per unit mass; SI units.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

__all__ = ["frictionless_steady_speed", "train_tilts"]


def _rotate(vec, theta):
    """Rotate body-frame vectors (x forward, y up) by a forward tilt ``theta`` [rad]."""
    c, s = np.cos(theta), np.sin(theta)
    return np.array([c * vec[0] + s * vec[1], -s * vec[0] + c * vec[1]])


def _corner_to_face(tilt, front_tilt, k, l, s, lam):
    """Signed distance [m] of domino k's top-front corner from domino k-1's back face.

    Domino ``j`` pivots about ``(-j lam, 0)`` (domino 0, the front, at the origin);
    positive while the corner is still behind the face.
    """
    corner = np.array([-k * lam, 0.0]) + _rotate(np.array([0.0, l]), tilt)
    pivot = np.array([-(k - 1) * lam, 0.0])
    back_bottom = pivot + _rotate(np.array([-s, 0.0]), front_tilt)
    outward = _rotate(np.array([-1.0, 0.0]), front_tilt)  # the back face's normal
    return float(np.dot(corner - back_bottom, outward))


def train_tilts(theta0, l, s, lam, n):
    """Tilts [rad] of the ``n`` dominoes of a train whose front is at ``theta0``."""
    tilts = [float(theta0)]
    for k in range(1, n):
        front = tilts[-1]
        tilts.append(
            brentq(
                _corner_to_face,
                front,
                front + np.pi / 2,  # the corner turns from the face's line past it
                args=(front, k, l, s, lam),
                xtol=1e-15,
                rtol=4 * np.finfo(float).eps,
            )
        )
    return np.array(tilts)


def _centre_heights(tilts, l, s):
    """Heights [m] of the centres of mass of dominoes at ``tilts``."""
    return np.array([_rotate(np.array([-s / 2, l / 2]), t)[1] for t in tilts])


def _inertia_sum(theta0, l, s, lam, n, h=1e-6):
    """``S = sum_k (d theta_k / d theta_0)^2`` by central differences (step ``h``)."""
    phi = (train_tilts(theta0 + h, l, s, lam, n) - train_tilts(theta0 - h, l, s, lam, n)) / (2 * h)
    return float(np.sum(phi**2))


def frictionless_steady_speed(l, s, d, g=9.81, nodes=24):
    """Steady front speed [m/s] of the endless frictionless train.

    ``l``, ``s``, ``d`` [m]. The train is cut where the tail's share of the motion,
    shrinking like ``(1 - lam sin theta_* / l)^k``, is below 1e-13.
    """
    lam = d + s
    n = int(np.log(1e-13) / np.log(1 - np.sqrt(lam**2 - s**2) / l)) + 2
    beta = np.arcsin(d / l)
    inertia = (l**2 + s**2) / 3.0
    rest = np.arccos(s / lam)
    released = g * (_centre_heights([0.0], l, s)[0] - _centre_heights([rest], l, s)[0])
    s0 = _inertia_sum(beta / 2 * 1e-9, l, s, lam, n)  # theta0 = 0 up to a negligible shift
    u_after = 2 * released / inertia * (s0 - 1.0) / s0
    v0 = g * np.sum(_centre_heights(train_tilts(0.0, l, s, lam, n), l, s))
    x, w = np.polynomial.legendre.leggauss(nodes)
    total = 0.0
    for xi, wi in zip(x, w, strict=True):
        theta = beta * (1 + xi) / 2
        tilts = train_tilts(theta, l, s, lam, n)
        v = g * np.sum(_centre_heights(tilts, l, s))
        u = (inertia * s0 * u_after + 2 * (v0 - v)) / (inertia * _inertia_sum(theta, l, s, lam, n))
        total += wi * beta / 2 / np.sqrt(u)
    return lam / total

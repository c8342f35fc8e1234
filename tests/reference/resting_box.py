"""A rigid box resting flat on the floor on n point contacts with linear springs: the
static load of each corner and the frequencies of small oscillations.

The box (mass m [kg], principal moments I = (I_xx, I_yy, I_zz) about its centre [kg m^2])
rests on n corners at horizontal offsets (x_i, y_i) [m] from the point below its centre,
symmetric (sum x_i = sum y_i = sum x_i y_i = 0); the centre is at height h [m] above the
corners. Each contact pushes with a normal spring k [N/m] on the corner's overlap and,
optionally, a tangential spring k_t [N/m] on its horizontal displacement (Cundall-Strack,
no sliding). At rest, by symmetry and force balance, each corner carries

    F_i = m g / n  at the overlap  delta_0 = m g / (n k).                          (R)

Small motions about rest: the centre's displacement (X, Y, Z) and the rotation vector
(psi_x, psi_y, psi_z). A corner at body offset (x_i, y_i, -h) overlaps the floor by
delta_0 - Z - y_i psi_x + x_i psi_y - h (psi_x^2 + psi_y^2)/2 (to second order, terms
that cancel in the sum over symmetric corners left out) and moves sideways by
(X - h psi_y - y_i psi_z, Y + h psi_x + x_i psi_z). With the weight's
m g Z and k n delta_0 = m g, the potential energy to second order is

    V2 = (n k / 2) Z^2 + (1/2)(k sum x_i^2 - m g h) psi_y^2 + (1/2)(k sum y_i^2 - m g h) psi_x^2
         + (k_t / 2) sum_i [(X - h psi_y - y_i psi_z)^2 + (Y + h psi_x + x_i psi_z)^2],

the -m g h from the preloaded springs' lever arm shrinking as the box tilts. The modes:

    bounce       omega^2 = n k / m,
    rocking      about y, coupled with sliding along x: the 2 x 2 problem
                 [[n k_t, -n k_t h], [-n k_t h, k sum x_i^2 - m g h + n k_t h^2]] against
                 diag(m, I_yy) (k_t = 0: omega^2 = (k sum x_i^2 - m g h) / I_yy and 0);
                 about x likewise with sum y_i^2 and I_xx,
    yaw          omega^2 = k_t sum (x_i^2 + y_i^2) / I_zz.

A planar box (2D, the xz plane) on n = 2 corners at x = +-s/2 has the bounce and the
rocking about y. A stack of N such boxes is a chain of masses and springs n k: each
interface carries the weight above it, and its vertical modes are the fixed-free chain's.
No import of dominowave. Units: SI.
"""

from __future__ import annotations

import math

import numpy as np

G = 9.81  # standard gravity [m/s^2]


def resting_corner_load(m, n, k, g=G):
    """(force per corner [N], static overlap [m]) of a box of mass ``m`` resting flat on
    ``n`` corners with springs ``k`` [N/m] (eq R): (m g / n, m g / (n k))."""
    return m * g / n, m * g / (n * k)


def _pair_frequencies(m, inertia, second_moment, h, k, kt, n, g):
    """The two angular frequencies [rad/s] (low, high) of rocking coupled with sliding:
    roots of det(K - omega^2 M) = 0 for the 2 x 2 problem of the module docstring."""
    k11, k12 = n * kt, -n * kt * h
    k22 = k * second_moment - m * g * h + n * kt * h * h
    # omega^4 m I - omega^2 (k11 I + k22 m) + (k11 k22 - k12^2) = 0
    b = k11 * inertia + k22 * m
    det = k11 * k22 - k12 * k12
    disc = math.sqrt(b * b - 4.0 * m * inertia * det)
    low = 2.0 * det / (b + disc)  # the smaller root of the quadratic, without cancellation
    high = (b + disc) / (2.0 * m * inertia)
    return math.sqrt(max(low, 0.0)), math.sqrt(high)


def resting_box_modes(m, inertia, corners, h, k, kt=0.0, g=G):
    """Angular frequencies [rad/s] of small oscillations of a box resting on springs.

    ``m`` [kg]; ``inertia`` (3,) principal moments about the centre [kg m^2]; ``corners``
    (n, 2) horizontal offsets (x_i, y_i) [m] of the contacts from below the centre
    (symmetric); ``h`` [m] height of the centre above them; ``k``, ``kt`` [N/m] normal and
    tangential stiffness per contact. Returns a dict: "bounce" omega, "rock_y" and
    "rock_x" (low, high) pairs, "yaw" omega (module docstring). A negative rocking
    stiffness k sum x^2 < m g h (a top-heavy box on soft springs) raises ValueError."""
    corners = np.asarray(corners, dtype=float)
    n = len(corners)
    x, y = corners[:, 0], corners[:, 1]
    if max(abs(x.sum()), abs(y.sum()), abs((x * y).sum())) > 1e-12 * (x @ x + y @ y):
        raise ValueError("corners must be symmetric about the centre (sum x = sum y = 0)")
    modes = {"bounce": math.sqrt(n * k / m)}
    for name, moment2, i_axis in (("rock_y", x @ x, inertia[1]), ("rock_x", y @ y, inertia[0])):
        if moment2 > 0.0 and k * moment2 <= m * g * h:
            raise ValueError(f"k = {k} is too soft to hold the box upright (k sum x^2 <= m g h)")
        if moment2 > 0.0:
            modes[name] = _pair_frequencies(m, i_axis, moment2, h, k, kt, n, g)
    modes["yaw"] = math.sqrt(kt * (x @ x + y @ y) / inertia[2])
    return modes


def stack_loads(m, n_boxes, n_corners, k, g=G):
    """A stack of ``n_boxes`` equal boxes (mass ``m`` [kg]) on the floor, each interface
    (box on box, or the lowest box on the floor) on ``n_corners`` springs ``k`` [N/m]:
    (force per corner [N] (n_boxes,), overlap [m] (n_boxes,)), interface 0 the floor. The
    interface under box i carries the weight of the n_boxes - i boxes above it:
    F_i = (n_boxes - i) m g / n_corners, delta_i = F_i / k."""
    above = np.arange(n_boxes, 0, -1, dtype=float)
    force = above * m * g / n_corners
    return force, force / k


def stack_bounce_frequencies(m, n_boxes, n_corners, k):
    """Angular frequencies [rad/s] (n_boxes,) of the vertical modes of the stack: a chain
    of equal masses m and interface springs K = n_corners k, fixed at the floor and free
    at the top, omega_j = 2 sqrt(K / m) sin((2j - 1) pi / (2 (2 N + 1))), j = 1..N
    (the fixed-free chain's standing waves)."""
    j = np.arange(1, n_boxes + 1)
    return 2.0 * np.sqrt(n_corners * k / m) * np.sin((2 * j - 1) * np.pi / (2 * (2 * n_boxes + 1)))

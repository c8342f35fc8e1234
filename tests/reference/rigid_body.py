"""Free rigid bodies: Euler's equations and the rotation of a unit quaternion.

Euler's equations of a torque-free body, in its principal frame (moments I_1, I_2, I_3
[kg m^2], body-frame angular velocity omega [rad/s]):

    I_1 omega_1' = (I_2 - I_3) omega_2 omega_3,
    I_2 omega_2' = (I_3 - I_1) omega_3 omega_1,
    I_3 omega_3' = (I_1 - I_2) omega_1 omega_2.

They conserve the kinetic energy (1/2) sum I_i omega_i^2 and |L|^2 = sum (I_i omega_i)^2.
Spun near the intermediate axis (I_1 < I_2 < I_3) the body flips (the tennis-racket, or
Dzhanibekov, effect). No import of dominowave. Units: SI.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp


def euler_rhs(inertia):
    """Right side of Euler's equations for principal moments ``inertia`` (3,) [kg m^2]:
    a function (t, omega) -> omega' [rad/s^2]."""
    i1, i2, i3 = (float(v) for v in inertia)

    def rhs(_t, w):
        return [
            (i2 - i3) * w[1] * w[2] / i1,
            (i3 - i1) * w[2] * w[0] / i2,
            (i1 - i2) * w[0] * w[1] / i3,
        ]

    return rhs


def free_rotation(inertia, omega0, times):
    """Body-frame angular velocity [rad/s], shape (len(times), 3), of a torque-free body
    with principal moments ``inertia`` (3,) [kg m^2] starting with ``omega0`` (3,) at
    t = 0, at ``times`` (increasing, from 0) [s]. scipy RK45, rtol 1e-11, atol 1e-13."""
    times = np.asarray(times, dtype=float)
    sol = solve_ivp(
        euler_rhs(inertia),
        (0.0, float(times[-1])),
        np.asarray(omega0, dtype=float),
        t_eval=times,
        rtol=1e-11,
        atol=1e-13,
    )
    return sol.y.T


def quaternion_matrix(q):
    """Rotation matrix (3, 3) of the unit quaternion ``q`` = (w, x, y, z): R v is the
    vector v of the body frame expressed in the world frame (Hamilton convention)."""
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )

"""The orientation kernels of the drift against closed forms.

The drift turns quaternions without calling sin, cos, sqrt or dividing when the angle of a
step is small (Taylor series of cos x and sin(x)/x, integrate.SMALL_HALF_ANGLE) and
rescales an orientation only once its norm is off by more than QUAT_NORM_TOLERANCE.
Each is checked here against the closed form evaluated with the C library's
trigonometric functions (NumPy), and across the switch to the libm branch.
"""

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from dominowave.dem.integrate import (
    QUAT_NORM_TOLERANCE,
    SMALL_HALF_ANGLE,
    _normalise,
    _turn_body_axis,
    _turn_world,
)


def _quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


def _axis_angle_quat(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])


unit = st.floats(-1.0, 1.0, allow_nan=False)
# half angles from 1e-9 to 5x the Taylor threshold (both branches)
half_angle = st.floats(1e-9, 5 * SMALL_HALF_ANGLE)


@settings(max_examples=300, deadline=None)
@given(unit, unit, unit, half_angle, st.floats(1e-7, 1e-3))
def test_validate_turn_world_against_axis_angle(ax, ay, az, half, dt):
    """exp(omega dt) q0 = (cos x, sin(x) e) q0 with x = |omega| dt / 2, for a general q0;
    the vector part of the turn itself to a few ulp of sin(x) (so that a wrong Taylor
    coefficient, whose error is far below the components' size, is still caught)."""
    axis = np.array([ax, ay, az])
    if np.linalg.norm(axis) < 1e-3:
        axis = np.array([0.0, 1.0, 0.0])
    e = axis / np.linalg.norm(axis)
    omega = e * (2.0 * half / dt)
    turn = _axis_angle_quat(e, 2.0 * half)
    q = np.array([[1.0, 0.0, 0.0, 0.0]])
    _turn_world(q, 0, omega[0], omega[1], omega[2], dt)
    assert abs(q[0, 0] - np.cos(half)) <= 2e-16
    assert np.linalg.norm(q[0, 1:] - np.sin(half) * e) <= 4e-15 * np.sin(half)
    q0 = _axis_angle_quat([0.2, 0.9, -0.4], 1.1)
    q = q0[None, :].copy()
    _turn_world(q, 0, omega[0], omega[1], omega[2], dt)
    np.testing.assert_allclose(q[0], _quat_mul(turn, q0), rtol=0, atol=1e-15)


def test_validate_turn_world_composes_to_the_total_angle():
    """10 000 small turns about one axis (Taylor branch) = one turn by the total angle."""
    e = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    dt, w = 1e-4, 17.0  # half angle 8.5e-4 per step
    q = np.array([[1.0, 0.0, 0.0, 0.0]])
    for _ in range(10_000):
        _turn_world(q, 0, *(w * e), dt)
        _normalise(q, 0)
    exact = _axis_angle_quat(e, 10_000 * w * dt)
    # round-off of 10^4 products, a random walk of ~1e-16 per step
    np.testing.assert_allclose(q[0], exact, rtol=0, atol=1e-13)


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2), st.floats(-10 * SMALL_HALF_ANGLE, 10 * SMALL_HALF_ANGLE), unit, unit)
def test_validate_turn_body_axis_against_quaternion_product(k, phi, la, lb):
    """q <- q (cos phi/2, sin phi/2 e_k), and the body components of L turned by -phi."""
    q0 = _axis_angle_quat([0.2, 0.9, -0.4], 1.1)
    q = q0[None, :].copy()
    L = np.array([la, lb, 0.7])
    out = _turn_body_axis(q, 0, L[0], L[1], L[2], k, phi)
    e = np.zeros(3)
    e[k] = 1.0
    np.testing.assert_allclose(q[0], _quat_mul(q0, _axis_angle_quat(e, phi)), atol=4e-16)
    # rotating the frame by phi about e_k turns the body components of L by -phi
    c, s = math.cos(phi), math.sin(phi)
    i, j = (k + 1) % 3, (k + 2) % 3
    expected = L.copy()
    expected[i] = c * L[i] + s * L[j]
    expected[j] = -s * L[i] + c * L[j]
    np.testing.assert_allclose(out, expected, atol=4e-16)


@settings(deadline=None)
@given(st.floats(-1e-9, 1e-9), st.floats(0.5, 2.0))
@example(3e-15, 1.0)  # inside the tolerance: left as it is (a rescale would change bits)
@example(-4e-15, 1.0)
@example(1e-12, 2.0)
def test_validate_normalise(small, large):
    """Off by more than QUAT_NORM_TOLERANCE: rescaled to unit norm (a few ulp); closer:
    left exactly as it is (the kernel decides on its own |q|^2, which is recomputed here
    the same way)."""
    base = _axis_angle_quat([1.0, 2.0, 3.0], 0.7)
    for factor in (1.0 + small, large):
        q = (factor * base)[None, :].copy()
        before = q[0].copy()
        n2 = before[0] * before[0] + before[1] * before[1] + before[2] * before[2]
        n2 += before[3] * before[3]
        _normalise(q, 0)
        if abs(n2 - 1.0) > QUAT_NORM_TOLERANCE:
            assert abs(float(q[0] @ q[0]) - 1.0) < 1e-15
            np.testing.assert_allclose(q[0], base, atol=4e-16)
        else:
            np.testing.assert_array_equal(q[0], before)

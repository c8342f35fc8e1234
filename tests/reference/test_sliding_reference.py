"""The sliding-contact reference checked against closed forms: a vertex over a face and
over a straight edge of a box."""

import math

import numpy as np
import pytest

from reference.sliding_contact import sliding_contact

KN, KT, MU = 1e4, 8e3, 0.3
HALF = np.array([0.02, 0.01, 0.01])


def _point_box(offset):
    """A point-like box A (zero extents) at ``offset`` from the fixed box B at the origin."""
    return sliding_contact(offset, np.eye(3), np.zeros(3), 0.001, np.zeros(3), np.eye(3), HALF,
                           0.001, (1.0, 0.0, 0.0), KN, KT, MU)  # fmt: skip


def test_vertex_over_a_face_is_pushed_up_and_back():
    force, energy, delta = _point_box((0.005, 0.0, 0.01 + 0.0018))
    assert delta == pytest.approx(2e-4, rel=1e-9)
    np.testing.assert_allclose(force, [-MU * KN * 2e-4, 0.0, KN * 2e-4], rtol=1e-9)
    assert energy == pytest.approx(0.5 * KN * 4e-8 + 0.5 * (MU * KN * 2e-4) ** 2 / KT, rel=1e-9)


def test_vertex_beyond_an_edge_is_pushed_along_the_radius():
    dx, dz = 0.0006, 0.0015
    force, _, delta = _point_box((0.02 + dx, 0.0, 0.01 + dz))
    dist = math.hypot(dx, dz)
    assert delta == pytest.approx(0.002 - dist, rel=1e-9)
    n = np.array([dx, 0.0, dz]) / dist
    t = np.array([dz, 0.0, -dx]) / dist  # the tangential direction of +x motion
    fn = KN * (0.002 - dist)
    np.testing.assert_allclose(force, fn * n - MU * fn * t, rtol=1e-9, atol=1e-15)


def test_apart_is_zero():
    force, energy, delta = _point_box((0.0, 0.0, 0.013))
    assert delta < 0 and energy == 0.0 and not force.any()

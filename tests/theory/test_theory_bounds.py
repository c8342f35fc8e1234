"""Validation of the contact force and base-slip regimes (section 2.4, eqs 36-42)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from dominowave import theory as th
from dominowave.theory import Regime

L, M, G = 0.05, 0.008, 9.81
K_STAR = M * G / L


@pytest.mark.parametrize("beta", [0.05, 0.4, 0.9, 1.3])
@pytest.mark.parametrize("ratio", [1.0, 1e4])
def test_validate_peak_force_impulse_balance(beta, ratio):
    """Eq 37 against eq 36 by quadrature: the horizontal impulse of the half-sine pulse
    equals the momentum m' Omega l cos(b) of the struck domino, m' = m / cos^2 b."""
    k = ratio * K_STAR
    fm = th.peak_contact_force(beta, L, M, k, G)
    t_c = th.collision_time(k, M, beta)
    impulse, _ = quad(lambda t: fm * np.sin(np.pi * t / t_c), 0, t_c, epsabs=0, epsrel=1e-13)
    m_prime = M / np.cos(beta) ** 2
    momentum = m_prime * th.omega_limit(beta, L, G) * L * np.cos(beta)
    assert np.cos(beta) * impulse == pytest.approx(momentum, rel=1e-12)


def test_peak_force_scaling_and_rigid_limit():
    """F_m ~ sqrt(k) (T_c ~ 1/sqrt(k)); infinite for rigid dominoes (T_c = 0)."""
    beta = np.linspace(0.1, 1.4, 8)
    f1 = th.peak_contact_force(beta, L, M, K_STAR, G)
    f100 = th.peak_contact_force(beta, L, M, 100 * K_STAR, G)
    np.testing.assert_allclose(f100 / f1, 10.0, rtol=1e-13)
    assert np.all(np.isinf(th.peak_contact_force(beta, L, M, np.inf, G)))
    # F_m / (m g) depends only on beta and k/k* (dimensionless groups)
    scaled = th.peak_contact_force(beta, 2 * L, 3 * M, 3 * M * G / (2 * L), G) / (3 * M * G)
    np.testing.assert_allclose(scaled, f1 / (M * G), rtol=1e-13)


def _moment(point, force, about):
    """z-component of (point - about) x force, in the x (forward) - y (up) plane."""
    r = np.subtract(point, about)
    return r[0] * force[1] - r[1] * force[0]


@pytest.mark.parametrize("beta", [0.2, 0.6, 1.2, 1.45])
@pytest.mark.parametrize("mu, s_over_l", [(0.3, 0.1), (0.6, 0.02), (0.1, 0.3)])
def test_validate_boundaries_from_moment_and_force_balance(beta, mu, s_over_l):
    """Eqs 38, 39, 41, 42 re-derived with explicit cross products for a block of height l,
    thickness s, weight m g, struck on its back face at height l cos(b) by a force of
    horizontal part F cos(b) (eq 36); friction mu N and normal force N = m g at the base."""
    l, m, g = 1.0, 1.0, 1.0
    s = s_over_l * l
    centre = (0.0, l / 2)
    contact = (-s / 2, l * np.cos(beta))
    push = (np.cos(beta), 0.0)  # horizontal part of a unit contact force
    # moment of the push about the centre of mass, per unit F
    arm_g = abs(_moment(contact, push, centre))
    friction_moment = abs(_moment((0.0, 0.0), (mu * m * g, 0.0), centre))
    normal_moment = abs(_moment((s / 2, 0.0), (0.0, m * g), centre))  # N at the base edge
    bounds = th.regime_boundaries(beta, mu, s_over_l)
    # eq 38: the push turns the block about G against friction and the shifted normal force
    assert bounds.rotation == pytest.approx((friction_moment + normal_moment) / arm_g / (m * g))
    # eq 39: horizontal push against sliding friction
    assert bounds.sliding == pytest.approx(mu * m * g / push[0] / (m * g))
    # eq 41: beyond the friction moment (contact below G only)
    if beta > np.pi / 3:
        assert bounds.friction_moment == pytest.approx(friction_moment / arm_g / (m * g))
    else:
        assert np.isnan(bounds.friction_moment)
    # eq 42: toppling moment about the front edge against gravity's restoring moment
    front = (s / 2, 0.0)
    topple_arm = abs(_moment(contact, push, front))
    gravity = abs(_moment(centre, (0.0, -m * g), front))
    assert bounds.toppling == pytest.approx(gravity / topple_arm / (m * g))


def test_validate_eq42_correction_gives_classic_slide_or_tip_rule():
    """Pure sliding (eq 39 and eq 42) is possible iff mu < s / (2 h), h = l cos b the
    height of the push -- the textbook tip-or-slide rule. The printed eq 42
    (s / (2 l cos b)) would make it mu < s / (2 l) for every beta."""
    s_over_l = 0.1
    beta = np.linspace(0.05, 1.55, 300)
    for mu in (0.02, 0.3):
        b = th.regime_boundaries(beta, mu, s_over_l)
        window = b.toppling > b.sliding
        np.testing.assert_array_equal(window, mu < s_over_l / (2 * np.cos(beta)))


def test_classification_examples_and_precedence():
    """Points of the (beta, F_m/mg) plane for mu = 0.3, s/l = 0.1 (Fig 5B)."""
    mu, s_over_l = 0.3, 0.1
    beta = [0.3, 0.3, 1.3, 1.3, 1.3, 1.45]
    force = [0.1, 50.0, 0.1, 2.8, 50.0, 3.0]
    code, name = th.classify_regime(beta, force, mu, s_over_l)
    expected = [
        Regime.PURE_ROTATION,
        Regime.FORWARD_ROTATION_SLIP,
        Regime.PURE_ROTATION,
        Regime.TRANSLATION,  # Case 1: eq 39 and eq 41
        Regime.BACKWARD_ROTATION_SLIP,
        Regime.TRANSLATION,  # Case 2 only: eq 39 and eq 42, below the eq 41 window
    ]
    np.testing.assert_array_equal(code, expected)
    assert list(name) == [th.REGIME_NAMES[c] for c in expected]
    b = th.regime_boundaries(1.3, mu, s_over_l)
    assert b.friction_moment < 2.8 < b.rotation and 2.8 > b.sliding > b.toppling
    b = th.regime_boundaries(1.45, mu, s_over_l)
    assert b.sliding < 3.0 < b.friction_moment and 3.0 < b.toppling
    # overlap of eq 38 and eq 42 (cos b (2 mu + 4 s/l) < s/l): rotation wins
    beta = 1.56
    b = th.regime_boundaries(beta, mu, s_over_l)
    f = 0.5 * (b.rotation + b.toppling)
    assert b.rotation < f < b.toppling and f > b.sliding
    assert th.classify_regime(beta, f, mu, s_over_l).code == Regime.BACKWARD_ROTATION_SLIP


def test_classification_broadcasts_and_infinite_force():
    beta = np.linspace(0.1, 1.5, 5)[:, None]
    force = np.array([0.0, 1.0, np.inf])
    result = th.classify_regime(beta, force, 0.3, 0.1)
    assert result.code.shape == result.name.shape == (5, 3)
    assert np.all(result.code[:, 0] == Regime.PURE_ROTATION)  # no force, no slip
    assert np.all(np.isin(result.code[:, 2], [2, 3]))  # rigid (F_m = inf): always slips


@settings(max_examples=50, deadline=None)
@given(
    beta=st.floats(0.01, np.pi / 2 - 0.01),
    f=st.floats(0.0, 1e3),
    mu=st.floats(0.0, 2.0),
    s_over_l=st.floats(0.0, 0.5),
)
def test_validate_classification_consistent_with_criteria(beta, f, mu, s_over_l):
    """Each code satisfies its defining inequalities; more friction never adds slip."""
    code = int(th.classify_regime(beta, f, mu, s_over_l).code)
    b = th.regime_boundaries(beta, mu, s_over_l)
    if code in (Regime.FORWARD_ROTATION_SLIP, Regime.BACKWARD_ROTATION_SLIP):
        assert f > b.rotation
        assert (code == Regime.BACKWARD_ROTATION_SLIP) == (beta > np.pi / 3)
    elif code == Regime.TRANSLATION:
        assert f > b.sliding and f <= b.rotation
    else:
        assert f <= b.rotation
    if code == Regime.PURE_ROTATION:
        assert int(th.classify_regime(beta, f, 2 * mu + 0.1, s_over_l).code) == Regime.PURE_ROTATION

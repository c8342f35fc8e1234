"""Validation of the contact force and base-slip regimes (section 2.4, eqs 36-42)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq

from dominowave import theory as th
from dominowave.theory import Regime
from reference.block_statics import block_moment_about_com, moment, sign_change_force

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


@pytest.mark.parametrize("beta", [0.2, 0.6, 1.2, 1.45])
@pytest.mark.parametrize("mu, s_over_l", [(0.3, 0.1), (0.6, 0.02), (0.1, 0.3)])
def test_validate_boundaries_from_signed_moment_balance(beta, mu, s_over_l):
    """Eqs 38, 39, 41, 42 as the force at which a signed balance (cross products, root
    by brentq) changes sign. Eq 38 for beta > pi/3 is backward rotation of a block
    sliding forwards (friction along -x), the normal force at the back edge. For
    beta < pi/3 the printed eq 38 is reproduced only with friction along +x (base
    sliding backwards, the paper's implicit assumption); with forward slip the signed
    balance gives (s/l - mu) / (cos b (2 cos b - 1)) instead."""
    s = s_over_l
    b = th.regime_boundaries(beta, mu, s_over_l)
    cos_b = np.cos(beta)
    if beta > np.pi / 3:
        # eq 38: backward tipping (counter-clockwise) against the normal force at the back edge
        eq38 = sign_change_force(lambda f: block_moment_about_com(f, beta, mu, s, -1, -s / 2))
        assert b.rotation == pytest.approx(eq38, rel=1e-10)
        assert block_moment_about_com(1.01 * eq38, beta, mu, s, -1, -s / 2) > 0  # backwards
        # eq 41 lower bound: contact moment = friction moment (normal force under G)
        eq41 = sign_change_force(lambda f: block_moment_about_com(f, beta, mu, s, -1, 0.0))
        assert b.friction_moment == pytest.approx(eq41, rel=1e-10)
    else:
        assert np.isnan(b.friction_moment)
        # forward tipping against the normal force at the front edge, friction along +x
        paper = sign_change_force(lambda f: block_moment_about_com(f, beta, mu, s, +1, s / 2))
        assert b.rotation == pytest.approx(paper, rel=1e-10)
        assert block_moment_about_com(1.01 * paper, beta, mu, s, +1, s / 2) < 0  # forwards
        signed = sign_change_force(lambda f: block_moment_about_com(f, beta, mu, s, -1, s / 2))
        assert signed == pytest.approx((s - mu) / (cos_b * (2 * cos_b - 1)), rel=1e-10)
        assert signed < b.rotation  # forward slip tips the block at a lower force
    # eq 39: horizontal push against kinetic friction
    assert b.sliding == pytest.approx(sign_change_force(lambda f: f * cos_b - mu), rel=1e-12)
    # eq 42: a block at rest (static friction and normal force at the front edge, no
    # moment there) tips about its front edge when the push beats gravity's moment
    front = (s / 2, 0.0)

    def about_front_edge(f):
        push = moment((-s / 2, cos_b), (f * cos_b, 0.0), front)
        return push + moment((0.0, 0.5), (0.0, -1.0), front)

    assert b.toppling == pytest.approx(sign_change_force(about_front_edge), rel=1e-10)
    assert about_front_edge(1.01 * b.toppling) < 0  # clockwise: tips forwards


@settings(max_examples=80, deadline=None)
@given(
    beta=st.floats(0.01, np.pi / 2 - 0.01),
    f=st.floats(0.0, 1e3),
    mu=st.floats(0.0, 2.0),
    s_over_l=st.floats(0.0, 0.5),
)
def test_validate_sliding_rotation_sign_from_cross_products(beta, f, mu, s_over_l):
    """A block sliding forwards stays upright iff some normal-force position
    |x_N| <= s/2 cancels the moment about G; otherwise it turns the way the moment does.
    Checked with the signed cross products, the normal force at both base edges."""
    sign = int(th.sliding_rotation_sign(beta, f, mu, s_over_l))
    at_back = block_moment_about_com(f, beta, mu, s_over_l, -1, -s_over_l / 2)
    at_front = block_moment_about_com(f, beta, mu, s_over_l, -1, s_over_l / 2)
    margin = 1e-9 * (1 + f)
    if at_back < -margin and at_front < -margin:
        assert sign == +1  # clockwise whatever the normal force does: tips forwards
    elif at_back > margin and at_front > margin:
        assert sign == -1
    elif at_back * at_front < -(margin**2):
        assert sign == 0
    if sign == -1:  # backward tipping of a sliding block is exactly eq 38 (beta > pi/3)
        assert beta > np.pi / 3 and f > th.regime_boundaries(beta, mu, s_over_l).rotation


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
    beta = [0.3, 0.3, 1.3, 1.3, 1.3, 1.45, 0.3, 1.3, 1.1]
    force = [0.1, 50.0, 0.1, 2.8, 50.0, 3.0, 0.35, 1.5, 6.0]
    code, name, by_paper = th.classify_regime(beta, force, mu, s_over_l)
    expected = [
        Regime.PURE_ROTATION,
        Regime.FORWARD_ROTATION_SLIP,
        Regime.PURE_ROTATION,
        Regime.TRANSLATION,  # Case 1: eq 39 and eq 41
        Regime.BACKWARD_ROTATION_SLIP,
        Regime.TRANSLATION,  # Case 2 only: eq 39 and eq 42, below the eq 41 window
        Regime.FORWARD_ROTATION_SLIP,  # eq 39 only: slides and tips forwards (signed)
        Regime.FORWARD_ROTATION_SLIP,  # eq 39 only, beta > pi/3: friction moment wins
        Regime.TRANSLATION,  # eq 39 only, beta > pi/3: normal force balances (signed)
    ]
    np.testing.assert_array_equal(code, expected)
    assert list(name) == [th.REGIME_NAMES[c] for c in expected]
    np.testing.assert_array_equal(by_paper, [True] * 6 + [False] * 3)
    b = th.regime_boundaries(1.3, mu, s_over_l)
    assert b.friction_moment < 2.8 < b.rotation and 2.8 > b.sliding > b.toppling
    assert b.sliding < 1.5 < b.friction_moment and 1.5 > b.toppling
    assert 1.5 * np.cos(1.3) * (1 - 2 * np.cos(1.3)) < mu - s_over_l  # friction moment wins
    b = th.regime_boundaries(1.45, mu, s_over_l)
    assert b.sliding < 3.0 < b.friction_moment and 3.0 < b.toppling
    b = th.regime_boundaries(0.3, mu, s_over_l)
    assert b.sliding < 0.35 < b.rotation and 0.35 > b.toppling
    cos_b = np.cos(1.1)  # between (mu - s/l) and mu on the scale of eq 41
    assert mu - s_over_l < 6.0 * cos_b * (1 - 2 * cos_b) < mu
    b = th.regime_boundaries(1.1, mu, s_over_l)
    assert b.toppling < b.sliding < 6.0 < b.friction_moment
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


@settings(max_examples=80, deadline=None)
@given(
    beta=st.floats(0.01, np.pi / 2 - 0.01),
    f=st.floats(0.0, 1e3),
    mu=st.floats(0.0, 2.0),
    s_over_l=st.floats(0.0, 0.5),
)
def test_validate_classification_consistent_with_criteria(beta, f, mu, s_over_l):
    """Each code satisfies its defining inequalities; I is exactly "eq 39 fails"; more
    friction never adds slip."""
    result = th.classify_regime(beta, f, mu, s_over_l)
    code, by_paper = int(result.code), bool(result.by_paper)
    b = th.regime_boundaries(beta, mu, s_over_l)
    below = beta > np.pi / 3
    assert (code == Regime.PURE_ROTATION) == (f <= b.sliding)  # eq 39
    if not by_paper:  # eq 39 only: decided by the signed balance of a sliding block
        assert f > b.sliding and f <= b.rotation and f >= b.toppling
        assert not (below and f > b.friction_moment)
        sign = int(th.sliding_rotation_sign(beta, f, mu, s_over_l))
        assert code == (Regime.FORWARD_ROTATION_SLIP if sign > 0 else Regime.TRANSLATION)
    elif code in (Regime.FORWARD_ROTATION_SLIP, Regime.BACKWARD_ROTATION_SLIP):
        assert f > b.rotation
        assert (code == Regime.BACKWARD_ROTATION_SLIP) == below
    elif code == Regime.TRANSLATION:
        assert f > b.sliding and f <= b.rotation
        assert f < b.toppling or (below and f > b.friction_moment)
    if code == Regime.PURE_ROTATION:
        assert int(th.classify_regime(beta, f, 2 * mu + 0.1, s_over_l).code) == Regime.PURE_ROTATION


@pytest.mark.parametrize("ratio, onset", [(1.0, 1.19513), (10.0, 1.47064), (100.0, 1.54032)])
def test_fig5b_curves_pure_rotation_only_where_friction_holds_the_base(ratio, onset):
    """Along the F_m/mg curves of Fig 5B (mu = 0.3, s/l = 0.1) no point with
    F_m cos b > mu m g is labelled I (the review counted 205 of 348 for k*), and I is
    the single band above the root of F_m cos b = mu m g (brentq)."""
    mu, s_over_l = 0.3, 0.1
    beta = np.linspace(0.01, np.pi / 2 - 0.005, 600)
    fm = th.peak_contact_force(beta, 1.0, 1.0, ratio, 1.0)
    code = th.classify_regime(beta, fm, mu, s_over_l).code
    pure = code == Regime.PURE_ROTATION
    assert not np.any(pure & (fm * np.cos(beta) > mu))
    root = brentq(
        lambda b: th.peak_contact_force(b, 1.0, 1.0, ratio, 1.0) * np.cos(b) - mu,
        0.5,
        np.pi / 2 - 1e-9,
        xtol=1e-14,
    )
    assert root == pytest.approx(onset, abs=1e-5)
    np.testing.assert_array_equal(pure, beta > root)
